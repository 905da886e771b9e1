#include "RenderTarget.h"

#include <stdexcept>
#include <string>

namespace pbf {

RenderTarget::RenderTarget(const GlFunctions& gl, TextureFormat color, const char* name,
                           bool mipmapped)
    : gl_(gl), color_format_(color), mipmapped_(mipmapped), name_(name) {
  gl_.GenFramebuffers(1, &framebuffer_);
  gl_.GenTextures(1, &color_);
}

RenderTarget::~RenderTarget() {
  gl_.DeleteFramebuffers(1, &framebuffer_);
  gl_.DeleteTextures(1, &color_);
}

void RenderTarget::resize(int width, int height) {
  if (width == width_ && height == height_) return;
  width_ = width;
  height_ = height;
  // Nearest sampling unless mipmapped: the passes read exact texels (texelFetch), and
  // filtering across the fluid silhouette would blend depth with background. (Only the
  // thickness is mipmapped: the composite reads it averaged over a particle's size.)
  gl_.BindTexture(GL_TEXTURE_2D, color_);
  gl_.TexImage2D(GL_TEXTURE_2D, 0, color_format_.internal_format, width, height, 0,
                 color_format_.format, color_format_.type, nullptr);
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER,
                    mipmapped_ ? GL_LINEAR_MIPMAP_LINEAR : GL_NEAREST);
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, mipmapped_ ? GL_LINEAR : GL_NEAREST);
  if (mipmapped_) gl_.GenerateMipmap(GL_TEXTURE_2D);  // allocate the levels
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  gl_.BindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  gl_.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, color_, 0);
  const GLenum status = gl_.CheckFramebufferStatus(GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE)
    throw std::runtime_error(std::string("render target '") + name_ +
                             "' is incomplete (status " + std::to_string(status) + ")");
  gl_.check(name_);
}

void RenderTarget::bindForDrawing() const {
  gl_.BindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  gl_.Viewport(0, 0, width_, height_);
}

void RenderTarget::generateMipmaps() const {
  gl_.BindTexture(GL_TEXTURE_2D, color_);
  gl_.GenerateMipmap(GL_TEXTURE_2D);
}

void RenderTarget::bindColorTexture(int unit) const {
  gl_.ActiveTexture(GL_TEXTURE0 + unit);
  gl_.BindTexture(GL_TEXTURE_2D, color_);
}

}  // namespace pbf
