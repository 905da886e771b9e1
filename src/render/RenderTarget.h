#pragma once
// A framebuffer object with one colour texture. Each pass of the pipeline draws into one
// of these and the next pass samples it. (No depth buffers: the sphere pass keeps the
// nearest sphere by MIN blending.)

#include "GlFunctions.h"

namespace pbf {

struct TextureFormat {
  GLint internal_format;  // e.g. GL_R32F
  GLenum format;          // e.g. GL_RED
  GLenum type;            // e.g. GL_FLOAT
};

class RenderTarget {
 public:
  // mipmapped: the colour texture is sampled with linear filtering from mipmap levels that
  // generateMipmaps() builds (the depth filters' prefiltered wide kernels); otherwise it
  // is read texel by texel.
  RenderTarget(const GlFunctions& gl, TextureFormat color, const char* name,
               bool mipmapped = false);
  ~RenderTarget();
  RenderTarget(const RenderTarget&) = delete;
  RenderTarget& operator=(const RenderTarget&) = delete;

  // (Re)allocates the textures if the size changed. Throws if the FBO is incomplete.
  void resize(int width, int height);
  // Binds the FBO and sets the viewport to its size.
  void bindForDrawing() const;
  void bindColorTexture(int unit) const;
  void generateMipmaps() const;

  GLuint framebuffer() const { return framebuffer_; }
  GLuint colorTexture() const { return color_; }
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  const GlFunctions& gl_;
  TextureFormat color_format_;
  bool mipmapped_;
  const char* name_;
  GLuint framebuffer_ = 0, color_ = 0;
  int width_ = 0, height_ = 0;
};

}  // namespace pbf
