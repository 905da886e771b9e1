// GPU images -> RenderOutput: rows flipped from GL's bottom-up to sensor_msgs' top-down,
// "no fluid" depth to NaN (REP 118), normals from GL view space to the optical frame.

#include <algorithm>
#include <limits>

#include "RenderContext.h"

namespace pbf {

template <typename T>
void RenderContext::readRowsTopDown(const RenderTarget& target, GLenum format, GLenum type,
                                    int channels, std::vector<T>& scratch,
                                    std::vector<T>& out) {
  const int w = target.width(), h = target.height();
  const std::size_t row = static_cast<std::size_t>(w) * channels;
  scratch.resize(row * h);
  out.resize(row * h);
  gl.BindFramebuffer(GL_FRAMEBUFFER, target.framebuffer());
  gl.ReadBuffer(GL_COLOR_ATTACHMENT0);
  gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
  gl.ReadPixels(0, 0, w, h, format, type, scratch.data());
  for (int y = 0; y < h; ++y)
    std::copy_n(scratch.data() + row * (h - 1 - y), row, out.data() + row * y);
}

void RenderContext::readBack(const RenderRequest& request, const RenderTarget& surface_depth,
                             RenderOutput& out) {
  if (request.image)
    readRowsTopDown(*color, GL_RGBA, GL_UNSIGNED_BYTE, 4, byte_scratch_, out.rgba);
  if (request.depth) {
    readRowsTopDown(surface_depth, GL_RED, GL_FLOAT, 1, float_scratch_, out.depth);
    for (float& d : out.depth)
      if (!(d > 0)) d = std::numeric_limits<float>::quiet_NaN();  // REP 118: no return
  }
  if (request.thickness)
    readRowsTopDown(*thickness, GL_RED, GL_FLOAT, 1, float_scratch_, out.thickness);
  if (request.normals) {
    readRowsTopDown(*normals, GL_RGBA, GL_FLOAT, 4, float_scratch_, normal_scratch_);
    const std::size_t pixels = normal_scratch_.size() / 4;
    out.normals.resize(pixels * 3);
    for (std::size_t i = 0; i < pixels; ++i) {
      const float* n = &normal_scratch_[4 * i];
      const bool fluid = n[3] > 0.5f;
      // GL view (x right, y up, z back) -> optical (x right, y down, z forward).
      out.normals[3 * i + 0] = fluid ? n[0] : 0.0f;
      out.normals[3 * i + 1] = fluid ? -n[1] : 0.0f;
      out.normals[3 * i + 2] = fluid ? -n[2] : 0.0f;
    }
  }
  gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
}

}  // namespace pbf
