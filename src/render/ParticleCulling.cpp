#include "ParticleCulling.h"

#include <cmath>
#include <stdexcept>

namespace pbf {

void selectVisibleParticles(const std::vector<Eigen::Vector3f>& positions, float radius,
                            const RenderCamera& camera,
                            const std::vector<std::uint32_t>* neighbor_counts,
                            bool surface_only, std::uint32_t interior_neighbor_count,
                            VisibleParticles& out) {
  if (neighbor_counts && neighbor_counts->size() != positions.size())
    throw std::invalid_argument("FluidRenderer: neighbor_counts has " +
                                std::to_string(neighbor_counts->size()) +
                                " entries for " + std::to_string(positions.size()) +
                                " particles");
  const bool split = surface_only && neighbor_counts;
  // World -> GL view, as one affine map.
  const Eigen::Matrix4f view = glViewFromWorld(camera);
  const Eigen::Matrix3f rotation = view.topLeftCorner<3, 3>();
  const Eigen::Vector3f translation = view.topRightCorner<3, 1>();

  // A sphere is outside a side plane through the eye when its centre is more than
  // `radius` beyond it; the plane x = tan_x * depth has unit normal (1, -tan_x)/sqrt(1+tan_x^2).
  const float tan_y = std::tan(0.5f * camera.vertical_fov);
  const float tan_x = tan_y * static_cast<float>(camera.width) / camera.height;
  const float slack_x = radius * std::sqrt(1.0f + tan_x * tan_x);
  const float slack_y = radius * std::sqrt(1.0f + tan_y * tan_y);
  const float near_limit = camera.near_clip - radius, far_limit = camera.far_clip + radius;

  out.view_positions.clear();
  out.view_positions.reserve(positions.size());
  std::vector<Eigen::Vector3f>& interior = out.interior_scratch;
  interior.clear();
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const Eigen::Vector3f v = rotation * positions[i] + translation;
    const float depth = -v.z();
    if (depth < near_limit || depth > far_limit) continue;
    if (std::abs(v.x()) > tan_x * depth + slack_x) continue;
    if (std::abs(v.y()) > tan_y * depth + slack_y) continue;
    if (split && (*neighbor_counts)[i] >= interior_neighbor_count)
      interior.push_back(v);
    else
      out.view_positions.push_back(v);
  }
  out.surface_count = out.view_positions.size();
  out.view_positions.insert(out.view_positions.end(), interior.begin(), interior.end());
}

}  // namespace pbf
