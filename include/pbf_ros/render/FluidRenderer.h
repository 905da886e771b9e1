#pragma once
// Headless screen-space fluid rendering (van der Laan et al. 2009, with the narrow-range
// depth filter of Truong & Yuksel 2018): particles -> sphere depth -> smoothed depth ->
// normals -> shaded water over a procedural floor, plus a metric depth image.
//
// Usage. The renderer owns its GL context, which is current on one thread at a time:
// construct, render and destroy it on the same (render) thread.
//   pbf::FluidRenderer renderer(pbf::createGlBackend("osmesa"), shader_dir);
//   pbf::RenderOutput out;
//   renderer.render(positions, radius, camera, pbf::RenderRequest{}, out);
//
// The shader directory holds the .vert/.frag files of the package's shaders/ folder.
// Errors (missing file, compile log, missing GL function) throw std::runtime_error.

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "pbf_ros/render/GlBackend.h"
#include "pbf_ros/render/RenderCamera.h"
#include "pbf_ros/render/RenderOptions.h"
#include "pbf_ros/render/RenderOutput.h"

namespace pbf {

class FluidRenderer {
 public:
  FluidRenderer(std::unique_ptr<GlBackend> backend, const std::string& shader_dir,
                const RenderOptions& options = {});
  ~FluidRenderer();
  FluidRenderer(const FluidRenderer&) = delete;
  FluidRenderer& operator=(const FluidRenderer&) = delete;

  void setOptions(const RenderOptions& options) { options_ = options; }
  const RenderOptions& options() const { return options_; }
  const GlBackend& backend() const { return *backend_; }
  // GL_VERSION and GL_RENDERER of the context, e.g. "4.5 (Core Profile) Mesa 22.3.6 / llvmpipe".
  std::string glDescription() const;

  // Renders what `request` asks for into `out` (buffers are reused between calls).
  // positions: particle centres in the world (fluid) frame; radius: particle radius (m).
  // neighbor_counts (optional, one per particle): used when
  // options().surface_particles_only is set.
  void render(const std::vector<Eigen::Vector3f>& positions, float radius,
              const RenderCamera& camera, const RenderRequest& request, RenderOutput& out,
              const std::vector<std::uint32_t>* neighbor_counts = nullptr);

 private:
  struct Impl;
  std::unique_ptr<GlBackend> backend_;
  RenderOptions options_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pbf
