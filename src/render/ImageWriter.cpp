#include "pbf_ros/render/ImageWriter.h"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

namespace pbf {

void writePng(const std::string& path, int width, int height, int channels,
              const std::vector<std::uint8_t>& pixels) {
  if (width <= 0 || height <= 0 ||
      pixels.size() != static_cast<std::size_t>(width) * height * channels)
    throw std::runtime_error("writePng(" + path + "): pixel buffer does not match the size");
  int color_type = 0;
  switch (channels) {
    case 1: color_type = PNG_COLOR_TYPE_GRAY; break;
    case 3: color_type = PNG_COLOR_TYPE_RGB; break;
    case 4: color_type = PNG_COLOR_TYPE_RGBA; break;
    default: throw std::runtime_error("writePng(" + path + "): channels must be 1, 3 or 4");
  }
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (!file) throw std::runtime_error("writePng: cannot open " + path + " for writing");
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    std::fclose(file);
    throw std::runtime_error("writePng: libpng failed writing " + path);
  }
  png_init_io(png, file);
  png_set_IHDR(png, info, width, height, 8, color_type, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (int row = 0; row < height; ++row)
    png_write_row(png, pixels.data() + static_cast<std::size_t>(row) * width * channels);
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  std::fclose(file);
}

std::vector<std::uint8_t> depthToRgba(const std::vector<float>& depth) {
  float lo = std::numeric_limits<float>::max(), hi = std::numeric_limits<float>::lowest();
  for (float d : depth)
    if (std::isfinite(d)) lo = std::min(lo, d), hi = std::max(hi, d);
  const float span = hi > lo ? hi - lo : 1.0f;
  std::vector<std::uint8_t> rgba(depth.size() * 4, 0);
  for (std::size_t i = 0; i < depth.size(); ++i) {
    rgba[4 * i + 3] = 255;
    if (!std::isfinite(depth[i])) continue;
    const float nearness = 1.0f - (depth[i] - lo) / span;
    const auto grey = static_cast<std::uint8_t>(40.0f + 215.0f * nearness);
    rgba[4 * i] = rgba[4 * i + 1] = rgba[4 * i + 2] = grey;
  }
  return rgba;
}

std::vector<std::uint8_t> normalsToRgba(const std::vector<float>& normals) {
  const std::size_t pixels = normals.size() / 3;
  std::vector<std::uint8_t> rgba(pixels * 4, 0);
  for (std::size_t i = 0; i < pixels; ++i) {
    rgba[4 * i + 3] = 255;
    const float* n = &normals[3 * i];
    if (n[0] == 0 && n[1] == 0 && n[2] == 0) continue;
    for (int c = 0; c < 3; ++c)
      rgba[4 * i + c] =
          static_cast<std::uint8_t>(std::clamp(127.5f * (n[c] + 1.0f), 0.0f, 255.0f));
  }
  return rgba;
}

std::vector<std::uint8_t> scalarToRgba(const std::vector<float>& values) {
  float hi = 0;
  for (float v : values)
    if (std::isfinite(v)) hi = std::max(hi, v);
  std::vector<std::uint8_t> rgba(values.size() * 4, 0);
  for (std::size_t i = 0; i < values.size(); ++i) {
    const float v = std::isfinite(values[i]) && hi > 0 ? values[i] / hi : 0.0f;
    rgba[4 * i] = rgba[4 * i + 1] = rgba[4 * i + 2] =
        static_cast<std::uint8_t>(255.0f * std::clamp(v, 0.0f, 1.0f));
    rgba[4 * i + 3] = 255;
  }
  return rgba;
}

}  // namespace pbf
