#include "pbf_ros/render/FluidRenderer.h"

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

#include "ParticleCulling.h"
#include "RenderContext.h"

namespace pbf {
namespace {

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

}  // namespace

struct FluidRenderer::Impl : RenderContext {
  using RenderContext::RenderContext;
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
  RenderContext& r = *impl_;
  // Each pass ends with glFinish so its time is its own (llvmpipe renders at flush time).
  auto lap = [&](double& slot) {
    r.gl.Finish();
    const Clock::time_point now = Clock::now();
    slot = millisecondsBetween(mark, now);
    mark = now;
  };

  backend_->makeCurrent();
  out.width = camera.width;
  out.height = camera.height;
  const bool need_thickness = request.image || request.thickness;
  const bool need_normals = request.image || request.normals;
  r.resize(camera.width, camera.height, request, options_);

  selectVisibleParticles(positions, radius, camera, neighbor_counts,
                         options_.surface_particles_only, options_.interior_neighbor_count,
                         r.visible);
  out.particles_in_view = r.visible.view_positions.size();
  // Thickness from every particle's chord, or, when only surface particles are to be drawn,
  // from the front and back faces of the surface (RenderContext::SecondOutput).
  const bool split = r.visible.surface_count < r.visible.view_positions.size();
  const auto second =
      split ? RenderContext::SecondOutput::FarDepth : RenderContext::SecondOutput::Chords;
  const bool together = need_thickness && r.gl.BlendEquationi;
  out.particles_in_depth = together && !split ? out.particles_in_view : r.visible.surface_count;
  r.uploadParticles();
  lap(out.timings.cull_upload);

  const Eigen::Matrix4f projection = glProjection(camera);
  const float focal = static_cast<float>(intrinsicsOf(camera).fy);
  const Eigen::Vector2f principal(0.5f * camera.width, 0.5f * camera.height);  // window coords

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
  if (request.image) {
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
