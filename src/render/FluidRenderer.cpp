#include "pbf_ros/render/FluidRenderer.h"

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

// The filters sample a half-disc of this many offset units; wider kernels step over
// several pixels per unit. 8 units = 100 mirrored pairs: enough taps for a smooth Gaussian,
// few enough for llvmpipe (see the benchmark).
constexpr int kFilterOffsetRadius = 8;
constexpr int kMaxFilterOffsets = 256;  // MAX_OFFSETS in the filter shaders

constexpr TextureFormat kFloatRed{GL_R32F, GL_RED, GL_FLOAT};
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
}

}  // namespace

struct FluidRenderer::Impl {
  GlFunctions gl;
  ShaderProgram depth_program, thickness_program, narrow_range_program, bilateral_program,
      normals_program, composite_program;
  std::unique_ptr<RenderTarget> raw_depth, thickness, smoothed_depth, normals, color;
  GLuint particle_vao = 0, particle_buffer = 0, fullscreen_vao = 0;
  VisibleParticles visible;
  std::vector<std::uint8_t> byte_scratch;
  std::vector<float> float_scratch;

  Impl(const GlBackend& backend, const std::string& dir) {
    gl.load(backend);
    GLint major = 0, minor = 0;
    gl.GetIntegerv(GL_MAJOR_VERSION, &major);
    gl.GetIntegerv(GL_MINOR_VERSION, &minor);
    if (major * 10 + minor < 33)
      throw std::runtime_error("GL backend '" + backend.name() + "' gives OpenGL " +
                               std::to_string(major) + "." + std::to_string(minor) +
                               "; the renderer needs 3.3 core");
    depth_program = ShaderProgram(gl, dir, "sphere_imposter.vert", "sphere_depth.frag");
    thickness_program = ShaderProgram(gl, dir, "sphere_imposter.vert", "sphere_thickness.frag");
    narrow_range_program = ShaderProgram(gl, dir, "fullscreen.vert", "narrow_range_filter.frag");
    bilateral_program = ShaderProgram(gl, dir, "fullscreen.vert", "bilateral_filter.frag");
    normals_program = ShaderProgram(gl, dir, "fullscreen.vert", "normals.frag");
    composite_program = ShaderProgram(gl, dir, "fullscreen.vert", "composite.frag");

    // Offsets are constant: set them once per filter program.
    const std::vector<float> offsets = halfDiscOffsets(kFilterOffsetRadius);
    const GLsizei offset_count = static_cast<GLsizei>(offsets.size() / 2);
    if (offset_count > kMaxFilterOffsets)
      throw std::logic_error("filter offsets exceed the shaders' MAX_OFFSETS");
    for (const ShaderProgram* program : {&narrow_range_program, &bilateral_program}) {
      program->use();
      gl.Uniform2fv(program->uniform("offsets"), offset_count, offsets.data());
      gl.Uniform1i(program->uniform("offset_count"), offset_count);
      gl.Uniform1f(program->uniform("offset_units_max"), static_cast<float>(kFilterOffsetRadius));
      gl.Uniform1i(program->uniform("depth_texture"), 0);
    }
    normals_program.use();
    gl.Uniform1i(normals_program.uniform("depth_texture"), 0);
    composite_program.use();
    gl.Uniform1i(composite_program.uniform("depth_texture"), 0);
    gl.Uniform1i(composite_program.uniform("normal_texture"), 1);
    gl.Uniform1i(composite_program.uniform("thickness_texture"), 2);
    gl.UseProgram(0);

    raw_depth = std::make_unique<RenderTarget>(gl, kFloatRed, true, "sphere depth");
    thickness = std::make_unique<RenderTarget>(gl, kFloatRed, false, "thickness");
    smoothed_depth = std::make_unique<RenderTarget>(gl, kFloatRed, false, "smoothed depth");
    normals = std::make_unique<RenderTarget>(gl, kHalfRgba, false, "normals");
    color = std::make_unique<RenderTarget>(gl, kByteRgba, false, "shaded image");

    gl.GenVertexArrays(1, &particle_vao);
    gl.GenBuffers(1, &particle_buffer);
    gl.BindVertexArray(particle_vao);
    gl.BindBuffer(GL_ARRAY_BUFFER, particle_buffer);
    gl.EnableVertexAttribArray(0);
    gl.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(Eigen::Vector3f), nullptr);
    gl.VertexAttribDivisor(0, 1);  // one sphere centre per instance
    gl.GenVertexArrays(1, &fullscreen_vao);  // core profile needs a VAO even without attributes
    gl.BindVertexArray(0);
    gl.check("FluidRenderer setup");
  }

  ~Impl() {
    gl.DeleteBuffers(1, &particle_buffer);
    gl.DeleteVertexArrays(1, &particle_vao);
    gl.DeleteVertexArrays(1, &fullscreen_vao);
  }

  void drawFullscreen() {
    gl.BindVertexArray(fullscreen_vao);
    gl.DrawArrays(GL_TRIANGLES, 0, 3);
  }

  // Reads the bound FBO's colour attachment, flipping GL's bottom-up rows to top-down.
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
  GlFunctions& gl = r.gl;
  // Each pass ends with glFinish so its time is its own (llvmpipe renders at flush time).
  auto lap = [&](double& slot) {
    gl.Finish();
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
  r.smoothed_depth->resize(w, h);
  if (need_thickness) r.thickness->resize(w, h);
  if (need_normals) r.normals->resize(w, h);
  if (need_shading) r.color->resize(w, h);

  // --- cull and upload ---
  selectVisibleParticles(positions, radius, camera, neighbor_counts,
                         options_.surface_particles_only, options_.interior_neighbor_count,
                         r.visible);
  const GLsizei all_count = static_cast<GLsizei>(r.visible.view_positions.size());
  const GLsizei surface_count = static_cast<GLsizei>(r.visible.surface_count);
  out.particles_in_view = r.visible.view_positions.size();
  out.particles_in_depth = r.visible.surface_count;
  gl.BindBuffer(GL_ARRAY_BUFFER, r.particle_buffer);
  gl.BufferData(GL_ARRAY_BUFFER, all_count * sizeof(Eigen::Vector3f),
                r.visible.view_positions.data(), GL_STREAM_DRAW);
  lap(out.timings.cull_upload);

  const Eigen::Matrix4f projection = glProjection(camera);
  const PinholeIntrinsics k = intrinsicsOf(camera);
  const float focal = static_cast<float>(k.fy);

  // --- 1. sphere depth ---
  r.raw_depth->bindForDrawing();
  gl.ClearColor(0, 0, 0, 0);
  gl.ClearDepth(1.0);
  gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  gl.Enable(GL_DEPTH_TEST);
  gl.DepthFunc(GL_LESS);
  gl.DepthMask(GL_TRUE);
  gl.Disable(GL_BLEND);
  r.depth_program.use();
  gl.UniformMatrix4fv(r.depth_program.uniform("projection"), 1, GL_FALSE, projection.data());
  gl.Uniform1f(r.depth_program.uniform("radius"), radius);
  gl.BindVertexArray(r.particle_vao);
  if (surface_count > 0) gl.DrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, surface_count);
  gl.Disable(GL_DEPTH_TEST);
  lap(out.timings.depth);

  // --- 2. thickness ---
  if (need_thickness) {
    r.thickness->bindForDrawing();
    gl.Clear(GL_COLOR_BUFFER_BIT);
    gl.Enable(GL_BLEND);
    gl.BlendEquation(GL_FUNC_ADD);
    gl.BlendFunc(GL_ONE, GL_ONE);
    r.thickness_program.use();
    gl.UniformMatrix4fv(r.thickness_program.uniform("projection"), 1, GL_FALSE,
                        projection.data());
    gl.Uniform1f(r.thickness_program.uniform("radius"), radius);
    gl.BindVertexArray(r.particle_vao);
    if (all_count > 0) gl.DrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, all_count);
    gl.Disable(GL_BLEND);
    lap(out.timings.thickness);
  }

  // --- 3. depth smoothing ---
  const RenderTarget* surface_depth = r.raw_depth.get();
  if (options_.filter != DepthFilter::None) {
    const bool narrow = options_.filter == DepthFilter::NarrowRange;
    const ShaderProgram& program = narrow ? r.narrow_range_program : r.bilateral_program;
    r.smoothed_depth->bindForDrawing();
    program.use();
    gl.Uniform1f(program.uniform("focal_pixels"), focal);
    gl.Uniform1f(program.uniform("sigma_world"), options_.filter_sigma_in_radii * radius);
    gl.Uniform1f(program.uniform("max_radius_pixels"),
                 static_cast<float>(options_.max_filter_radius_pixels));
    if (narrow) {
      gl.Uniform1f(program.uniform("threshold"),
                   options_.narrow_range_threshold_in_radii * radius);
      gl.Uniform1f(program.uniform("clamp_distance"),
                   options_.narrow_range_clamp_in_radii * radius);
    } else {
      gl.Uniform1f(program.uniform("depth_sigma"),
                   options_.bilateral_depth_sigma_in_radii * radius);
    }
    r.raw_depth->bindColorTexture(0);
    r.drawFullscreen();
    surface_depth = r.smoothed_depth.get();
    lap(out.timings.filter);
  }

  // --- 4. normals ---
  const Eigen::Vector2f principal(0.5f * w, 0.5f * h);  // window coordinates
  if (need_normals) {
    r.normals->bindForDrawing();
    r.normals_program.use();
    gl.Uniform1f(r.normals_program.uniform("focal_pixels"), focal);
    gl.Uniform2f(r.normals_program.uniform("principal_point"), principal.x(), principal.y());
    surface_depth->bindColorTexture(0);
    r.drawFullscreen();
    lap(out.timings.normals);
  }

  // --- 5. composite ---
  if (need_shading) {
    const ShaderProgram& p = r.composite_program;
    r.color->bindForDrawing();
    p.use();
    const Eigen::Matrix3f world_from_view =
        glViewFromWorld(camera).topLeftCorner<3, 3>().transpose();
    const Eigen::Vector3f eye = camera.camera_to_world.translation();
    const Eigen::Vector3f light = options_.light_direction.normalized();
    gl.Uniform1f(p.uniform("focal_pixels"), focal);
    gl.Uniform2f(p.uniform("principal_point"), principal.x(), principal.y());
    gl.UniformMatrix3fv(p.uniform("world_from_view"), 1, GL_FALSE, world_from_view.data());
    gl.Uniform3f(p.uniform("eye_world"), eye.x(), eye.y(), eye.z());
    gl.Uniform1f(p.uniform("refractive_index"), options_.refractive_index);
    gl.Uniform1f(p.uniform("fresnel_f0"), options_.fresnel_f0);
    gl.Uniform3f(p.uniform("absorption"), options_.absorption.x(), options_.absorption.y(),
                 options_.absorption.z());
    gl.Uniform3f(p.uniform("light_direction"), light.x(), light.y(), light.z());
    gl.Uniform1f(p.uniform("specular_strength"), options_.specular_strength);
    gl.Uniform1f(p.uniform("specular_exponent"), options_.specular_exponent);
    gl.Uniform1f(p.uniform("floor_height"), options_.floor_height);
    gl.Uniform1f(p.uniform("floor_tile_size"), options_.floor_tile_size);
    gl.Uniform1i(p.uniform("draw_background"), options_.draw_background ? 1 : 0);
    surface_depth->bindColorTexture(0);
    r.normals->bindColorTexture(1);
    r.thickness->bindColorTexture(2);
    r.drawFullscreen();
    lap(out.timings.composite);
  }
  gl.check("FluidRenderer::render passes");

  // --- readback, rows top-down ---
  if (request.image)
    r.readRowsTopDown(*r.color, GL_RGBA, GL_UNSIGNED_BYTE, 4, r.byte_scratch, out.rgba);
  if (request.depth) {
    r.readRowsTopDown(*surface_depth, GL_RED, GL_FLOAT, 1, r.float_scratch, out.depth);
    for (float& d : out.depth)
      if (!(d > 0)) d = std::numeric_limits<float>::quiet_NaN();  // REP 118: no return
  }
  if (request.thickness)
    r.readRowsTopDown(*r.thickness, GL_RED, GL_FLOAT, 1, r.float_scratch, out.thickness);
  if (request.normals) {
    std::vector<float> rgba;
    r.readRowsTopDown(*r.normals, GL_RGBA, GL_FLOAT, 4, r.float_scratch, rgba);
    out.normals.resize(static_cast<std::size_t>(w) * h * 3);
    for (std::size_t i = 0, n = static_cast<std::size_t>(w) * h; i < n; ++i) {
      const bool fluid = rgba[4 * i + 3] > 0.5f;
      // GL view (x right, y up, z back) -> optical (x right, y down, z forward).
      out.normals[3 * i + 0] = fluid ? rgba[4 * i + 0] : 0.0f;
      out.normals[3 * i + 1] = fluid ? -rgba[4 * i + 1] : 0.0f;
      out.normals[3 * i + 2] = fluid ? -rgba[4 * i + 2] : 0.0f;
    }
  }
  gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
  gl.check("FluidRenderer::render readback");
  lap(out.timings.readback);
  out.timings.total = millisecondsBetween(start, Clock::now());
  out.rendered = true;
}

}  // namespace pbf
