#include "RenderContext.h"

#include <stdexcept>

#include "FilterOffsets.h"

namespace pbf {
namespace {

// The filters' offsets reach this many units (filter_kernel.glsl): a half-disc of ~100
// mirrored pairs, the cost bound of one pixel on llvmpipe (see pbf_render_bench); wider
// kernels (up to twice this many pixels) take every other pixel of the prefiltered depth.
constexpr int kFilterOffsetRadius = 8;
constexpr int kMaxFilterOffsets = 128;  // MAX_OFFSETS in filter_kernel.glsl
// Sigma of the prefilter (prefilter_depth.frag): enough to keep a 2-pixel grid from
// aliasing (it attenuates the grid's alias frequency, 1/2 cycle per pixel, by e^-7),
// small next to the smoothing kernel itself.
constexpr float kPrefilterSigmaPixels = 1.2f;

constexpr TextureFormat kFloatRed{GL_R32F, GL_RED, GL_FLOAT};
constexpr TextureFormat kFloatRg{GL_RG32F, GL_RG, GL_FLOAT};
constexpr TextureFormat kHalfRgba{GL_RGBA16F, GL_RGBA, GL_FLOAT};
constexpr TextureFormat kByteRgba{GL_RGBA8, GL_RGBA, GL_UNSIGNED_BYTE};

}  // namespace

RenderContext::RenderContext(const GlBackend& backend, const std::string& dir) {
  gl.load(backend);
  GLint major = 0, minor = 0;
  gl.GetIntegerv(GL_MAJOR_VERSION, &major);
  gl.GetIntegerv(GL_MINOR_VERSION, &minor);
  if (major * 10 + minor < 33)
    throw std::runtime_error("GL backend '" + backend.name() + "' gives OpenGL " +
                             std::to_string(major) + "." + std::to_string(minor) +
                             "; the renderer needs 3.3 core");
  sphere_program_ = ShaderProgram(gl, dir, "sphere_imposter.vert", "sphere_surface.frag");
  close_gaps_program_ = ShaderProgram(gl, dir, "fullscreen.vert", "close_gaps.frag");
  prefilter_program_ = ShaderProgram(gl, dir, "fullscreen.vert", "prefilter_depth.frag");
  narrow_range_program_ = ShaderProgram(gl, dir, "fullscreen.vert", "narrow_range_filter.frag");
  bilateral_program_ = ShaderProgram(gl, dir, "fullscreen.vert", "bilateral_filter.frag");
  thickness_program_ = ShaderProgram(gl, dir, "fullscreen.vert", "thickness_from_depths.frag");
  normals_program_ = ShaderProgram(gl, dir, "fullscreen.vert", "normals.frag");
  background_program_ = ShaderProgram(gl, dir, "fullscreen.vert", "background.frag");
  composite_program_ = ShaderProgram(gl, dir, "fullscreen.vert", "composite.frag");

  // Constant uniforms: texture units and the filters' offsets.
  sphere_program_.use();
  gl.Uniform1i(sphere_program_.uniform("centers_view"), kUnitCenters);
  close_gaps_program_.use();
  gl.Uniform1i(close_gaps_program_.uniform("depth_texture"), kUnitInput);
  gl.Uniform1i(close_gaps_program_.uniform("coverage_texture"), kUnitSecondInput);
  prefilter_program_.use();
  gl.Uniform1i(prefilter_program_.uniform("depth_texture"), kUnitInput);
  gl.Uniform1i(prefilter_program_.uniform("coverage_texture"), kUnitSecondInput);
  gl.Uniform1f(prefilter_program_.uniform("sigma_pixels"), kPrefilterSigmaPixels);
  const std::vector<float> offsets = halfDiscOffsets(kFilterOffsetRadius);
  const GLsizei offset_count = static_cast<GLsizei>(offsets.size() / 2);
  if (offset_count > kMaxFilterOffsets)
    throw std::logic_error("filter offsets exceed the shaders' MAX_OFFSETS");
  for (const ShaderProgram* program : {&narrow_range_program_, &bilateral_program_}) {
    program->use();
    gl.Uniform2fv(program->uniform("offsets"), offset_count, offsets.data());
    gl.Uniform1i(program->uniform("offset_count"), offset_count);
    gl.Uniform1f(program->uniform("offset_units_max"), static_cast<float>(kFilterOffsetRadius));
    gl.Uniform1i(program->uniform("depth_texture"), kUnitInput);
  }
  thickness_program_.use();
  gl.Uniform1i(thickness_program_.uniform("near_texture"), kUnitInput);
  gl.Uniform1i(thickness_program_.uniform("far_texture"), kUnitSecondInput);
  normals_program_.use();
  gl.Uniform1i(normals_program_.uniform("depth_texture"), kUnitInput);
  composite_program_.use();
  gl.Uniform1i(composite_program_.uniform("depth_texture"), kUnitInput);
  gl.Uniform1i(composite_program_.uniform("normal_texture"), kUnitSecondInput);
  gl.Uniform1i(composite_program_.uniform("thickness_texture"), kUnitThickness);
  gl.Uniform1i(composite_program_.uniform("background_texture"), kUnitBackground);
  gl.UseProgram(0);

  raw_depth = std::make_unique<RenderTarget>(gl, kFloatRed, "sphere depth");
  far_depth = std::make_unique<RenderTarget>(gl, kFloatRed, "far sphere depth");
  gap_half = std::make_unique<RenderTarget>(gl, kFloatRg, "gap closing, 1st axis");
  closed_depth = std::make_unique<RenderTarget>(gl, kFloatRg, "gap-closed depth");
  prefilter_half = std::make_unique<RenderTarget>(gl, kFloatRg, "prefilter, 1st axis");
  prefiltered_depth = std::make_unique<RenderTarget>(gl, kFloatRg, "prefiltered depth");
  thickness = std::make_unique<RenderTarget>(gl, kFloatRed, "thickness", true);
  smoothed_depth = std::make_unique<RenderTarget>(gl, kFloatRed, "smoothed depth");
  normals = std::make_unique<RenderTarget>(gl, kHalfRgba, "normals");
  background = std::make_unique<RenderTarget>(gl, kByteRgba, "background");
  color = std::make_unique<RenderTarget>(gl, kByteRgba, "shaded image");

  gl.GenFramebuffers(1, &sphere_framebuffer_);
  gl.GenBuffers(1, &particle_buffer_);
  gl.GenTextures(1, &particle_texture_);
  // Every draw fetches or builds its vertices in the shader; core profile still needs a VAO.
  gl.GenVertexArrays(1, &empty_vao_);
  gl.BindVertexArray(empty_vao_);
  gl.check("FluidRenderer setup");
}

RenderContext::~RenderContext() {
  gl.DeleteFramebuffers(1, &sphere_framebuffer_);
  gl.DeleteTextures(1, &particle_texture_);
  gl.DeleteBuffers(1, &particle_buffer_);
  gl.DeleteVertexArrays(1, &empty_vao_);
}

void RenderContext::resize(int w, int h, const RenderRequest& request, const RenderOptions& o) {
  raw_depth->resize(w, h);
  gap_half->resize(w, h);
  closed_depth->resize(w, h);
  if (o.filter != DepthFilter::None) {
    prefilter_half->resize(w, h);
    prefiltered_depth->resize(w, h);
    smoothed_depth->resize(w, h);
  }
  if (request.image || request.thickness) {
    thickness->resize(w, h);
    far_depth->resize(w, h);
  }
  if (request.image || request.normals) normals->resize(w, h);
  if (request.image) {
    background->resize(w, h);
    color->resize(w, h);
  }
}

void RenderContext::beginScreenPass(const RenderTarget& target, const GLfloat* clear_value) {
  target.bindForDrawing();
  gl.Disable(GL_SCISSOR_TEST);
  gl.ClearBufferfv(GL_COLOR, 0, clear_value);
  limitToFluid();
}

void RenderContext::limitToFluid() {
  gl.Enable(GL_SCISSOR_TEST);
  gl.Scissor(visible.x_begin, visible.y_begin, visible.x_end - visible.x_begin,
             visible.y_end - visible.y_begin);
}

}  // namespace pbf
