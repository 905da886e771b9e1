#include "pbf_ros/render/FluidRenderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "FilterOffsets.h"
#include "GlFunctions.h"
#include "ParticleCulling.h"
#include "RenderTarget.h"
#include "ShaderProgram.h"

namespace pbf {
namespace {

// The filters' offsets reach this many units (filter_kernel.glsl): a half-disc of ~100
// mirrored pairs, the cost bound of one pixel on llvmpipe (see pbf_render_bench); wider
// kernels (up to twice this many pixels) take every other pixel of the prefiltered depth.
constexpr int kFilterOffsetRadius = 8;
// Sigma of the prefilter (prefilter_depth.frag): enough to keep a 2-pixel grid from
// aliasing (it attenuates the grid's alias frequency, 1/2 cycle per pixel, by e^-7),
// small next to the smoothing kernel itself.
constexpr float kPrefilterSigmaPixels = 1.2f;
constexpr int kMaxFilterOffsets = 128;  // MAX_OFFSETS in filter_kernel.glsl

// Texture units, bound to each program's samplers once at set-up: a pass reads its main
// input (depth of some stage) on unit 0 and a second one (normals, coverage, far depth) on
// unit 1.
constexpr int kUnitInput = 0, kUnitSecondInput = 1, kUnitThickness = 2, kUnitCenters = 3,
              kUnitBackground = 4;

constexpr GLfloat kClearDepth[4] = {1e30f, 0, 0, 0};  // "no fluid" for MIN blending
constexpr GLfloat kClearZero[4] = {0, 0, 0, 0};

constexpr TextureFormat kFloatRed{GL_R32F, GL_RED, GL_FLOAT};
constexpr TextureFormat kFloatRg{GL_RG32F, GL_RG, GL_FLOAT};
constexpr TextureFormat kHalfRgba{GL_RGBA16F, GL_RGBA, GL_FLOAT};
constexpr TextureFormat kByteRgba{GL_RGBA8, GL_RGBA, GL_UNSIGNED_BYTE};

using Clock = std::chrono::steady_clock;
double millisecondsBetween(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

void validate(float radius, const RenderCamera& camera) {
  if (!(radius > 0) || !std::isfinite(radius))
    throw std::invalid_argument("FluidRenderer: particle radius must be positive, got " +
                                std::to_string(radius));
  if (camera.width <= 0 || camera.height <= 0)
    throw std::invalid_argument("FluidRenderer: camera size must be positive, got " +
                                std::to_string(camera.width) + "x" +
                                std::to_string(camera.height));
  if (!(camera.vertical_fov > 0 && camera.vertical_fov < 3.1f))
    throw std::invalid_argument("FluidRenderer: vertical_fov must be in (0, pi) radians");
  if (!(camera.near_clip > 0 && camera.far_clip > camera.near_clip))
    throw std::invalid_argument("FluidRenderer: need 0 < near_clip < far_clip");
  if (!camera.camera_to_world.matrix().allFinite())
    throw std::invalid_argument("FluidRenderer: camera pose is not finite");
}

// Everything the cached background depends on.
std::vector<float> backgroundKey(const RenderCamera& c, const RenderOptions& o) {
  std::vector<float> key(c.camera_to_world.matrix().data(),
                         c.camera_to_world.matrix().data() + 16);
  key.insert(key.end(), {c.vertical_fov, static_cast<float>(c.width),
                         static_cast<float>(c.height), o.floor_height, o.floor_tile_size,
                         o.light_direction.x(), o.light_direction.y(), o.light_direction.z(),
                         o.draw_background ? 1.0f : 0.0f});
  return key;
}

}  // namespace

struct FluidRenderer::Impl {
  GlFunctions gl;
  ShaderProgram sphere_program, narrow_range_program, bilateral_program,
      normals_program, background_program, composite_program, close_gaps_program,
      prefilter_program, thickness_program;
  std::unique_ptr<RenderTarget> raw_depth, far_depth, gap_half, closed_depth, prefilter_half,
      prefiltered_depth,
      thickness, smoothed_depth, normals, background, color;
  // Draws depth and thickness in one pass (both targets attached), when GL >= 4.0.
  GLuint sphere_framebuffer = 0;
  // Sphere centres: a buffer object read by the imposter vertex shader as a buffer texture.
  GLuint particle_buffer = 0, particle_texture = 0, empty_vao = 0;
  VisibleParticles visible;
  std::vector<float> background_key;  // what the cached background was drawn for
  std::vector<std::uint8_t> byte_scratch;
  std::vector<float> float_scratch, normal_scratch;

  Impl(const GlBackend& backend, const std::string& dir) {
    gl.load(backend);
    GLint major = 0, minor = 0;
    gl.GetIntegerv(GL_MAJOR_VERSION, &major);
    gl.GetIntegerv(GL_MINOR_VERSION, &minor);
    if (major * 10 + minor < 33)
      throw std::runtime_error("GL backend '" + backend.name() + "' gives OpenGL " +
                               std::to_string(major) + "." + std::to_string(minor) +
                               "; the renderer needs 3.3 core");
    sphere_program = ShaderProgram(gl, dir, "sphere_imposter.vert", "sphere_surface.frag");
    narrow_range_program = ShaderProgram(gl, dir, "fullscreen.vert", "narrow_range_filter.frag");
    bilateral_program = ShaderProgram(gl, dir, "fullscreen.vert", "bilateral_filter.frag");
    normals_program = ShaderProgram(gl, dir, "fullscreen.vert", "normals.frag");
    background_program = ShaderProgram(gl, dir, "fullscreen.vert", "background.frag");
    composite_program = ShaderProgram(gl, dir, "fullscreen.vert", "composite.frag");
    close_gaps_program = ShaderProgram(gl, dir, "fullscreen.vert", "close_gaps.frag");
    prefilter_program = ShaderProgram(gl, dir, "fullscreen.vert", "prefilter_depth.frag");
    thickness_program =
        ShaderProgram(gl, dir, "fullscreen.vert", "thickness_from_depths.frag");

    // Constant uniforms: texture units and the filters' offsets.
    sphere_program.use();
    gl.Uniform1i(sphere_program.uniform("centers_view"), kUnitCenters);
    const std::vector<float> offsets = halfDiscOffsets(kFilterOffsetRadius);
    const GLsizei offset_count = static_cast<GLsizei>(offsets.size() / 2);
    if (offset_count > kMaxFilterOffsets)
      throw std::logic_error("filter offsets exceed the shaders' MAX_OFFSETS");
    for (const ShaderProgram* program : {&narrow_range_program, &bilateral_program}) {
      program->use();
      gl.Uniform2fv(program->uniform("offsets"), offset_count, offsets.data());
      gl.Uniform1i(program->uniform("offset_count"), offset_count);
      gl.Uniform1f(program->uniform("offset_units_max"),
                   static_cast<float>(kFilterOffsetRadius));
      gl.Uniform1i(program->uniform("depth_texture"), kUnitInput);
    }
    normals_program.use();
    gl.Uniform1i(normals_program.uniform("depth_texture"), kUnitInput);
    close_gaps_program.use();
    gl.Uniform1i(close_gaps_program.uniform("depth_texture"), kUnitInput);
    gl.Uniform1i(close_gaps_program.uniform("coverage_texture"), kUnitSecondInput);
    thickness_program.use();
    gl.Uniform1i(thickness_program.uniform("near_texture"), kUnitInput);
    gl.Uniform1i(thickness_program.uniform("far_texture"), kUnitSecondInput);
    prefilter_program.use();
    gl.Uniform1i(prefilter_program.uniform("depth_texture"), kUnitInput);
    gl.Uniform1i(prefilter_program.uniform("coverage_texture"), kUnitSecondInput);
    gl.Uniform1f(prefilter_program.uniform("sigma_pixels"), kPrefilterSigmaPixels);
    composite_program.use();
    gl.Uniform1i(composite_program.uniform("depth_texture"), kUnitInput);
    gl.Uniform1i(composite_program.uniform("normal_texture"), kUnitSecondInput);
    gl.Uniform1i(composite_program.uniform("thickness_texture"), kUnitThickness);
    gl.Uniform1i(composite_program.uniform("background_texture"), kUnitBackground);
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

    gl.GenFramebuffers(1, &sphere_framebuffer);
    gl.GenBuffers(1, &particle_buffer);
    gl.GenTextures(1, &particle_texture);
    // Every draw fetches or builds its vertices in the shader; core profile still needs a VAO.
    gl.GenVertexArrays(1, &empty_vao);
    gl.BindVertexArray(empty_vao);
    gl.check("FluidRenderer setup");
  }

  ~Impl() {
    gl.DeleteFramebuffers(1, &sphere_framebuffer);
    gl.DeleteTextures(1, &particle_texture);
    gl.DeleteBuffers(1, &particle_buffer);
    gl.DeleteVertexArrays(1, &empty_vao);
  }

  void drawFullscreen() { gl.DrawArrays(GL_TRIANGLES, 0, 3); }

  // One triangle per sphere; see sphere_imposter.vert.
  void drawSpheres(GLsizei count) {
    if (count > 0) gl.DrawArrays(GL_TRIANGLES, 0, 3 * count);
  }

  // Clears the whole target, then limits drawing to the fluid's bounding rectangle: the
  // screen-space passes cost nothing outside the fluid.
  void beginScreenPass(const RenderTarget& target, const GLfloat* clear_value = kClearZero) {
    target.bindForDrawing();
    gl.Disable(GL_SCISSOR_TEST);
    gl.ClearBufferfv(GL_COLOR, 0, clear_value);
    gl.Enable(GL_SCISSOR_TEST);
    gl.Scissor(visible.x_begin, visible.y_begin, visible.x_end - visible.x_begin,
               visible.y_end - visible.y_begin);
  }

  void uploadParticles() {
    gl.BindBuffer(GL_TEXTURE_BUFFER, particle_buffer);
    gl.BufferData(GL_TEXTURE_BUFFER, visible.view_positions.size() * sizeof(Eigen::Vector4f),
                  visible.view_positions.data(), GL_STREAM_DRAW);
    gl.ActiveTexture(GL_TEXTURE0 + kUnitCenters);
    gl.BindTexture(GL_TEXTURE_BUFFER, particle_texture);
    gl.TexBuffer(GL_TEXTURE_BUFFER, GL_RGBA32F, particle_buffer);
  }

  // What the sphere pass's second output accumulates (sphere_surface.frag).
  enum class SecondOutput {
    Chords,    // summed chord lengths, ADD-blended into `thickness`: every particle
    FarDepth,  // depth of the farthest sphere back face, MAX-blended into `far_depth`:
               // surface particles only, thickness resolved afterwards as far - near
  };

  void setSphereUniforms(const Eigen::Matrix4f& projection, float radius, SecondOutput second) {
    sphere_program.use();
    gl.UniformMatrix4fv(sphere_program.uniform("projection"), 1, GL_FALSE, projection.data());
    gl.Uniform1f(sphere_program.uniform("radius"), radius);
    gl.Uniform1i(sphere_program.uniform("far_depth_output"),
                 second == SecondOutput::FarDepth ? 1 : 0);
  }

  RenderTarget& secondTarget(SecondOutput second) {
    return second == SecondOutput::FarDepth ? *far_depth : *thickness;
  }
  static GLenum secondEquation(SecondOutput second) {
    return second == SecondOutput::FarDepth ? GL_MAX : GL_FUNC_ADD;
  }
  GLsizei secondCount(SecondOutput second) const {
    return static_cast<GLsizei>(second == SecondOutput::FarDepth ? visible.surface_count
                                                                  : visible.view_positions.size());
  }

  // Depth target cleared to "no fluid", then MIN-blended (sphere_surface.frag, output 0).
  void drawSphereDepth(const Eigen::Matrix4f& projection, float radius) {
    raw_depth->bindForDrawing();
    const GLenum outputs[] = {GL_COLOR_ATTACHMENT0};
    gl.DrawBuffers(1, outputs);
    gl.Disable(GL_SCISSOR_TEST);
    gl.ClearBufferfv(GL_COLOR, 0, kClearDepth);
    gl.Enable(GL_BLEND);
    gl.BlendFunc(GL_ONE, GL_ONE);
    gl.BlendEquation(GL_MIN);
    setSphereUniforms(projection, radius, SecondOutput::Chords);
    drawSpheres(static_cast<GLsizei>(visible.surface_count));
    gl.Disable(GL_BLEND);
  }

  // The second output alone (output 1 routed to the target's only attachment).
  void drawSecondOutput(const Eigen::Matrix4f& projection, float radius, SecondOutput second) {
    RenderTarget& target = secondTarget(second);
    target.bindForDrawing();
    const GLenum outputs[] = {GL_NONE, GL_COLOR_ATTACHMENT0};
    gl.DrawBuffers(2, outputs);
    gl.Disable(GL_SCISSOR_TEST);
    gl.ClearBufferfv(GL_COLOR, 1, kClearZero);
    gl.Enable(GL_BLEND);
    gl.BlendFunc(GL_ONE, GL_ONE);
    gl.BlendEquation(secondEquation(second));
    setSphereUniforms(projection, radius, second);
    drawSpheres(secondCount(second));
    gl.Disable(GL_BLEND);
  }

  // Both outputs from one draw (GL 4.0: a blend equation per target). With FarDepth both
  // need only the surface particles; with Chords every particle is drawn.
  void drawSphereDepthAndSecond(const Eigen::Matrix4f& projection, float radius,
                                SecondOutput second) {
    RenderTarget& target = secondTarget(second);
    gl.BindFramebuffer(GL_FRAMEBUFFER, sphere_framebuffer);
    gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D,
                            raw_depth->colorTexture(), 0);
    gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D,
                            target.colorTexture(), 0);
    const GLenum outputs[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    gl.DrawBuffers(2, outputs);
    if (gl.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw std::runtime_error("render target 'sphere depth + thickness' is incomplete");
    gl.Viewport(0, 0, raw_depth->width(), raw_depth->height());
    gl.Disable(GL_SCISSOR_TEST);
    gl.ClearBufferfv(GL_COLOR, 0, kClearDepth);
    gl.ClearBufferfv(GL_COLOR, 1, kClearZero);
    gl.Enable(GL_BLEND);
    gl.BlendFunc(GL_ONE, GL_ONE);
    gl.BlendEquationi(0, GL_MIN);
    gl.BlendEquationi(1, secondEquation(second));
    setSphereUniforms(projection, radius, second);
    drawSpheres(secondCount(second));
    gl.Disable(GL_BLEND);
  }

  // thickness = (far - near) * packing, where the surface-only sphere pass left the
  // nearest front face in raw_depth and the farthest back face in far_depth.
  void resolveThicknessFromDepths() {
    beginScreenPass(*thickness);
    thickness_program.use();
    raw_depth->bindColorTexture(kUnitInput);
    far_depth->bindColorTexture(kUnitSecondInput);
    drawFullscreen();
  }

  // (depth, coverage) pairs from the sphere depth, with the gaps closed (close_gaps.frag,
  // a pass along x and one along y). gap_fraction 0 only converts.
  void resolveDepth(float gap_fraction, float focal, float radius) {
    // How far the erosion can matter: 1.5 reach at the nearest sphere (beyond that a
    // neighbour must be 2.25 radii nearer, another surface, not a gap), at most 6 pixels;
    // at least 2, to fill pinholes.
    const float reach = visible.nearest_depth > 0
                            ? gap_fraction * radius * focal / visible.nearest_depth
                            : 0.0f;
    const int extent =
        gap_fraction <= 0 ? 0 : std::clamp(static_cast<int>(std::ceil(1.5f * reach)), 2, 6);
    close_gaps_program.use();
    gl.Uniform1f(close_gaps_program.uniform("focal_pixels"), focal);
    gl.Uniform1f(close_gaps_program.uniform("radius"), radius);
    gl.Uniform1f(close_gaps_program.uniform("gap_fraction"), std::max(gap_fraction, 1e-3f));
    gl.Uniform1i(close_gaps_program.uniform("extent"), extent);
    const RenderTarget* source = raw_depth.get();
    if (extent > 0) {
      beginScreenPass(*gap_half, kClearDepth);  // read beyond the rectangle: no fluid
      gl.Uniform2i(close_gaps_program.uniform("direction"), 1, 0);
      gl.Uniform1i(close_gaps_program.uniform("final_pass"), 0);
      raw_depth->bindColorTexture(kUnitInput);
      drawFullscreen();
      source = gap_half.get();
    }
    beginScreenPass(*closed_depth);
    gl.Uniform2i(close_gaps_program.uniform("direction"), 0, 1);
    gl.Uniform1i(close_gaps_program.uniform("final_pass"), 1);
    source->bindColorTexture(kUnitInput);
    raw_depth->bindColorTexture(kUnitSecondInput);  // coverage
    drawFullscreen();
  }

  void smoothDepth(const RenderOptions& o, float focal, float radius) {
    // After resolveDepth: a light separable blur (prefilter_depth.frag), then the 2-D
    // smoothing filter.
    prefilter_program.use();
    beginScreenPass(*prefilter_half);
    gl.Uniform2i(prefilter_program.uniform("direction"), 1, 0);
    gl.Uniform1i(prefilter_program.uniform("final_pass"), 0);
    closed_depth->bindColorTexture(kUnitInput);
    drawFullscreen();
    beginScreenPass(*prefiltered_depth);
    gl.Uniform2i(prefilter_program.uniform("direction"), 0, 1);
    gl.Uniform1i(prefilter_program.uniform("final_pass"), 1);
    prefilter_half->bindColorTexture(kUnitInput);
    closed_depth->bindColorTexture(kUnitSecondInput);  // the coverage to keep
    drawFullscreen();

    const bool narrow = o.filter == DepthFilter::NarrowRange;
    const ShaderProgram& program = narrow ? narrow_range_program : bilateral_program;
    beginScreenPass(*smoothed_depth);
    program.use();
    gl.Uniform1f(program.uniform("focal_pixels"), focal);
    gl.Uniform1f(program.uniform("sigma_world"), o.filter_sigma_in_radii * radius);
    gl.Uniform1f(program.uniform("max_radius_pixels"),
                 static_cast<float>(o.max_filter_radius_pixels));
    if (narrow) {
      gl.Uniform1f(program.uniform("threshold"), o.narrow_range_threshold_in_radii * radius);
      gl.Uniform1f(program.uniform("clamp_distance"), o.narrow_range_clamp_in_radii * radius);
    } else {
      gl.Uniform1f(program.uniform("depth_sigma"), o.bilateral_depth_sigma_in_radii * radius);
    }
    prefiltered_depth->bindColorTexture(kUnitInput);
    drawFullscreen();
  }

  void computeNormals(const RenderTarget& surface_depth, float focal,
                      const Eigen::Vector2f& principal) {
    beginScreenPass(*normals);
    normals_program.use();
    gl.Uniform1f(normals_program.uniform("focal_pixels"), focal);
    gl.Uniform2f(normals_program.uniform("principal_point"), principal.x(), principal.y());
    surface_depth.bindColorTexture(kUnitInput);
    drawFullscreen();
  }

  // Sets the uniforms of procedural_scene.glsl and the camera ray uniforms.
  void setSceneUniforms(const ShaderProgram& p, const RenderCamera& camera,
                        const RenderOptions& o, float focal, const Eigen::Vector2f& principal) {
    const Eigen::Matrix3f world_from_view =
        glViewFromWorld(camera).topLeftCorner<3, 3>().transpose();
    const Eigen::Vector3f eye = camera.camera_to_world.translation();
    const Eigen::Vector3f light = o.light_direction.normalized();
    gl.Uniform1f(p.uniform("focal_pixels"), focal);
    gl.Uniform2f(p.uniform("principal_point"), principal.x(), principal.y());
    gl.UniformMatrix3fv(p.uniform("world_from_view"), 1, GL_FALSE, world_from_view.data());
    gl.Uniform3f(p.uniform("eye_world"), eye.x(), eye.y(), eye.z());
    gl.Uniform3f(p.uniform("light_direction"), light.x(), light.y(), light.z());
    gl.Uniform1f(p.uniform("floor_height"), o.floor_height);
    gl.Uniform1f(p.uniform("floor_tile_size"), o.floor_tile_size);
  }

  void updateBackground(const RenderCamera& camera, const RenderOptions& o, float focal,
                        const Eigen::Vector2f& principal) {
    std::vector<float> key = backgroundKey(camera, o);
    if (key == background_key) return;  // unchanged camera and scene: keep the cached one
    background->bindForDrawing();
    gl.Disable(GL_SCISSOR_TEST);
    background_program.use();
    setSceneUniforms(background_program, camera, o, focal, principal);
    gl.Uniform1i(background_program.uniform("draw_background"), o.draw_background ? 1 : 0);
    drawFullscreen();
    background_key = std::move(key);
  }

  void composite(const RenderTarget& surface_depth, const RenderCamera& camera,
                 const RenderOptions& o, float focal, const Eigen::Vector2f& principal,
                 float radius) {
    // The background everywhere (a copy), then the fluid shaded inside its rectangle.
    gl.BindFramebuffer(GL_READ_FRAMEBUFFER, background->framebuffer());
    gl.BindFramebuffer(GL_DRAW_FRAMEBUFFER, color->framebuffer());
    gl.Disable(GL_SCISSOR_TEST);
    gl.BlitFramebuffer(0, 0, camera.width, camera.height, 0, 0, camera.width, camera.height,
                       GL_COLOR_BUFFER_BIT, GL_NEAREST);
    color->bindForDrawing();
    gl.Enable(GL_SCISSOR_TEST);
    gl.Scissor(visible.x_begin, visible.y_begin, visible.x_end - visible.x_begin,
               visible.y_end - visible.y_begin);
    const ShaderProgram& p = composite_program;
    p.use();
    setSceneUniforms(p, camera, o, focal, principal);
    gl.Uniform1f(p.uniform("refractive_index"), o.refractive_index);
    gl.Uniform1f(p.uniform("fresnel_f0"), o.fresnel_f0);
    gl.Uniform3f(p.uniform("absorption"), o.absorption.x(), o.absorption.y(), o.absorption.z());
    gl.Uniform1f(p.uniform("specular_strength"), o.specular_strength);
    gl.Uniform1f(p.uniform("specular_exponent"), o.specular_exponent);
    gl.Uniform1f(p.uniform("radius"), radius);
    surface_depth.bindColorTexture(kUnitInput);
    normals->bindColorTexture(kUnitSecondInput);
    thickness->bindColorTexture(kUnitThickness);
    thickness->generateMipmaps();
    background->bindColorTexture(kUnitBackground);
    drawFullscreen();
    gl.Disable(GL_SCISSOR_TEST);
  }

  // Reads a target's colour attachment, flipping GL's bottom-up rows to top-down.
  template <typename T>
  void readRowsTopDown(const RenderTarget& target, GLenum format, GLenum type, int channels,
                       std::vector<T>& scratch, std::vector<T>& out) {
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

  void readBack(const RenderRequest& request, const RenderTarget& surface_depth,
                RenderOutput& out) {
    if (request.image)
      readRowsTopDown(*color, GL_RGBA, GL_UNSIGNED_BYTE, 4, byte_scratch, out.rgba);
    if (request.depth) {
      readRowsTopDown(surface_depth, GL_RED, GL_FLOAT, 1, float_scratch, out.depth);
      for (float& d : out.depth)
        if (!(d > 0)) d = std::numeric_limits<float>::quiet_NaN();  // REP 118: no return
    }
    if (request.thickness)
      readRowsTopDown(*thickness, GL_RED, GL_FLOAT, 1, float_scratch, out.thickness);
    if (request.normals) {
      readRowsTopDown(*normals, GL_RGBA, GL_FLOAT, 4, float_scratch, normal_scratch);
      const std::size_t pixels = normal_scratch.size() / 4;
      out.normals.resize(pixels * 3);
      for (std::size_t i = 0; i < pixels; ++i) {
        const float* n = &normal_scratch[4 * i];
        const bool fluid = n[3] > 0.5f;
        // GL view (x right, y up, z back) -> optical (x right, y down, z forward).
        out.normals[3 * i + 0] = fluid ? n[0] : 0.0f;
        out.normals[3 * i + 1] = fluid ? -n[1] : 0.0f;
        out.normals[3 * i + 2] = fluid ? -n[2] : 0.0f;
      }
    }
    gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
  }
};

FluidRenderer::FluidRenderer(std::unique_ptr<GlBackend> backend, const std::string& shader_dir,
                             const RenderOptions& options)
    : backend_(std::move(backend)), options_(options) {
  if (!backend_) throw std::invalid_argument("FluidRenderer: no GL backend given");
  backend_->makeCurrent();
  impl_ = std::make_unique<Impl>(*backend_, shader_dir);
}

FluidRenderer::~FluidRenderer() {
  // GL objects must be deleted while their context is current (and before it goes).
  try {
    backend_->makeCurrent();
  } catch (...) {
  }
  impl_.reset();
}

std::string FluidRenderer::glDescription() const {
  backend_->makeCurrent();
  auto text = [this](GLenum what) {
    const GLubyte* s = impl_->gl.GetString(what);
    return s ? std::string(reinterpret_cast<const char*>(s)) : std::string("?");
  };
  return text(GL_VERSION) + " / " + text(GL_RENDERER);
}

void FluidRenderer::render(const std::vector<Eigen::Vector3f>& positions, float radius,
                           const RenderCamera& camera, const RenderRequest& request,
                           RenderOutput& out,
                           const std::vector<std::uint32_t>* neighbor_counts) {
  out.timings = RenderTimings{};
  out.rendered = false;
  out.particles_in_view = out.particles_in_depth = 0;
  if (!request.image) out.rgba.clear();
  if (!request.depth) out.depth.clear();
  if (!request.thickness) out.thickness.clear();
  if (!request.normals) out.normals.clear();
  if (!request.any()) return;  // nobody is looking: no GL work at all
  validate(radius, camera);

  const Clock::time_point start = Clock::now();
  Clock::time_point mark = start;
  Impl& r = *impl_;
  // Each pass ends with glFinish so its time is its own (llvmpipe renders at flush time).
  auto lap = [&](double& slot) {
    r.gl.Finish();
    const Clock::time_point now = Clock::now();
    slot = millisecondsBetween(mark, now);
    mark = now;
  };

  backend_->makeCurrent();
  const int w = camera.width, h = camera.height;
  out.width = w;
  out.height = h;
  const bool need_shading = request.image;
  const bool need_thickness = request.image || request.thickness;
  const bool need_normals = request.image || request.normals;
  r.raw_depth->resize(w, h);
  r.gap_half->resize(w, h);
  r.closed_depth->resize(w, h);
  if (options_.filter != DepthFilter::None) {
    r.prefilter_half->resize(w, h);
    r.prefiltered_depth->resize(w, h);
    r.smoothed_depth->resize(w, h);
  }
  if (need_thickness) {
    r.thickness->resize(w, h);
    r.far_depth->resize(w, h);
  }
  if (need_normals) r.normals->resize(w, h);
  if (need_shading) {
    r.background->resize(w, h);
    r.color->resize(w, h);
  }

  selectVisibleParticles(positions, radius, camera, neighbor_counts,
                         options_.surface_particles_only, options_.interior_neighbor_count,
                         r.visible);
  out.particles_in_view = r.visible.view_positions.size();
  // Thickness from every particle's chord, or, when only surface particles are to be drawn,
  // from the front and back faces of the surface (Impl::SecondOutput).
  const bool split = r.visible.surface_count < r.visible.view_positions.size();
  const auto second = split ? Impl::SecondOutput::FarDepth : Impl::SecondOutput::Chords;
  const bool together = need_thickness && r.gl.BlendEquationi;
  out.particles_in_depth = together && !split ? out.particles_in_view : r.visible.surface_count;
  r.uploadParticles();
  lap(out.timings.cull_upload);

  const Eigen::Matrix4f projection = glProjection(camera);
  const float focal = static_cast<float>(intrinsicsOf(camera).fy);
  const Eigen::Vector2f principal(0.5f * w, 0.5f * h);  // window coordinates

  if (together) {
    r.drawSphereDepthAndSecond(projection, radius, second);
    lap(out.timings.depth);
  } else {
    r.drawSphereDepth(projection, radius);
    lap(out.timings.depth);
    if (need_thickness) r.drawSecondOutput(projection, radius, second);
  }
  if (need_thickness && split) r.resolveThicknessFromDepths();
  if (need_thickness) lap(out.timings.thickness);
  const bool smooth = options_.filter != DepthFilter::None;
  r.resolveDepth(smooth ? options_.gap_closing_in_radii : 0.0f, focal, radius);
  const RenderTarget* surface_depth = r.closed_depth.get();
  if (smooth) {
    r.smoothDepth(options_, focal, radius);
    surface_depth = r.smoothed_depth.get();
  }
  lap(out.timings.filter);
  if (need_normals) {
    r.computeNormals(*surface_depth, focal, principal);
    lap(out.timings.normals);
  }
  if (need_shading) {
    r.updateBackground(camera, options_, focal, principal);
    r.composite(*surface_depth, camera, options_, focal, principal, radius);
    lap(out.timings.composite);
  }
  r.gl.Disable(GL_SCISSOR_TEST);
  r.gl.check("FluidRenderer::render passes");

  r.readBack(request, *surface_depth, out);
  r.gl.check("FluidRenderer::render readback");
  lap(out.timings.readback);
  out.timings.total = millisecondsBetween(start, Clock::now());
  out.rendered = true;
}

}  // namespace pbf
