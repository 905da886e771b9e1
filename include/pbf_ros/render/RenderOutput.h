#pragma once
// What the caller asks FluidRenderer for, and what it gets back.

#include <cstdint>
#include <vector>

namespace pbf {

// Nothing is rendered that nobody asked for: a request with every flag false costs nothing,
// and depth-only requests skip the thickness and composite passes.
struct RenderRequest {
  bool image = true;       // shaded RGBA8
  bool depth = true;       // smoothed depth, metres along the optical axis, NaN = no fluid
  bool thickness = false;  // summed chords of the particle spheres along each pixel's ray
                           // (m, 0 = none): about half the fluid's thickness, since
                           // touching spheres fill ~52 % of a lattice. With surface
                           // particles only: pi/6 * (back face - front face depth).
  bool normals = false;    // surface normals in the optical camera frame (0 = none)

  bool any() const { return image || depth || thickness || normals; }
};

// Milliseconds per pass, each bounded by glFinish (so they add up to the frame time).
struct RenderTimings {
  double cull_upload = 0;  // frustum culling, surface selection, upload to GL
  double depth = 0;        // sphere imposters -> linear depth (and thickness, see below)
  double thickness = 0;    // additive sphere chords; 0 when drawn in the depth pass (GL 4)
  double filter = 0;       // gap closing and depth smoothing
  double normals = 0;      // normals from smoothed depth
  double composite = 0;    // shading
  double readback = 0;     // glReadPixels and row flipping
  double total = 0;        // whole render() call
};

// Images are row-major with rows top-down (sensor_msgs order), width * height pixels.
// A vector is left empty when its image was not requested.
struct RenderOutput {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgba;  // 4 bytes per pixel
  std::vector<float> depth;        // 1 float per pixel
  std::vector<float> thickness;    // 1 float per pixel
  std::vector<float> normals;      // 3 floats per pixel, unit length or all 0
  RenderTimings timings;
  std::size_t particles_in_view = 0;   // after frustum culling
  std::size_t particles_in_depth = 0;  // drawn in the depth pass (surface only if enabled)
  bool rendered = false;               // false when the request was empty
};

}  // namespace pbf
