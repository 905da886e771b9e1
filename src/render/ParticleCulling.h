#pragma once
// CPU-side selection of what the GPU draws: particles whose sphere touches the view
// frustum, with the surface particles first so the depth pass can draw just those.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "pbf_ros/render/RenderCamera.h"

namespace pbf {

struct VisibleParticles {
  // Sphere centres in GL view space (x right, y up, z backwards): surface particles in
  // [0, surface_count), interior ones after them.
  std::vector<Eigen::Vector3f> view_positions;
  std::size_t surface_count = 0;
  std::vector<Eigen::Vector3f> interior_scratch;  // reused between frames
};

// neighbor_counts may be null (then every particle counts as surface). A particle is
// interior when neighbor_counts[i] >= interior_neighbor_count and surface_only is set.
void selectVisibleParticles(const std::vector<Eigen::Vector3f>& positions, float radius,
                            const RenderCamera& camera,
                            const std::vector<std::uint32_t>* neighbor_counts,
                            bool surface_only, std::uint32_t interior_neighbor_count,
                            VisibleParticles& out);

}  // namespace pbf
