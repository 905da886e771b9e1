#pragma once
// Small helpers to look at renderer output: PNG files and false-colour visualisations.
// Images are row-major, rows top-down, as in RenderOutput.

#include <cstdint>
#include <string>
#include <vector>

namespace pbf {

// Writes 8-bit RGBA (channels = 4), RGB (3) or grey (1). Throws std::runtime_error naming
// the file on failure.
void writePng(const std::string& path, int width, int height, int channels,
              const std::vector<std::uint8_t>& pixels);

// Depth (NaN = none) to grey RGBA: near bright, far dark, over the finite range; none = black.
std::vector<std::uint8_t> depthToRgba(const std::vector<float>& depth);
// Normals (3 floats per pixel) to RGBA as (n + 1) / 2; none = black.
std::vector<std::uint8_t> normalsToRgba(const std::vector<float>& normals);
// Non-negative scalar image to grey RGBA, scaled by its maximum.
std::vector<std::uint8_t> scalarToRgba(const std::vector<float>& values);

}  // namespace pbf
