#pragma once
// CPU-side selection of what the GPU draws: particles whose sphere touches the view
// frustum, with the surface particles first so the depth pass can draw just those.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "pbf_ros/render/RenderCamera.h"

namespace pbf {

struct VisibleParticles {
  // Sphere centres in GL view space (x right, y up, z backwards; w unused, it pads to the
  // RGBA32F texel of a GL 3.3 buffer texture): surface particles in [0, surface_count),
  // interior ones after them.
  std::vector<Eigen::Vector4f> view_positions;
  std::size_t surface_count = 0;
  // Window-space pixel rectangle (GL: x right, y up from the bottom row) that holds every
  // visible sphere's silhouette; the screen-space passes run only inside it. Empty
  // (x_end <= x_begin) when nothing is visible.
  int x_begin = 0, y_begin = 0, x_end = 0, y_end = 0;
  // Depth (along the optical axis) of the nearest visible sphere centre; 0 if none.
  float nearest_depth = 0;
  std::vector<Eigen::Vector4f> interior_scratch;  // reused between frames
};

// neighbor_counts may be null (then every particle counts as surface). A particle is
// interior when neighbor_counts[i] >= interior_neighbor_count and surface_only is set.
void selectVisibleParticles(const std::vector<Eigen::Vector3f>& positions, float radius,
                            const RenderCamera& camera,
                            const std::vector<std::uint32_t>* neighbor_counts,
                            bool surface_only, std::uint32_t interior_neighbor_count,
                            VisibleParticles& out);

}  // namespace pbf
