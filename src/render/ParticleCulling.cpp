#include "ParticleCulling.h"

#include <algorithm>
#include <cmath>
#include <limits>
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

  const float focal = static_cast<float>(intrinsicsOf(camera).fy);
  const float half_w = 0.5f * camera.width, half_h = 0.5f * camera.height;
  float x_min = std::numeric_limits<float>::max(), y_min = x_min;
  float x_max = std::numeric_limits<float>::lowest(), y_max = x_max;
  float nearest_centre = std::numeric_limits<float>::max();

  out.view_positions.clear();
  out.view_positions.reserve(positions.size());
  std::vector<Eigen::Vector4f>& interior = out.interior_scratch;
  interior.clear();
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const Eigen::Vector3f v = rotation * positions[i] + translation;
    if (!v.allFinite()) continue;  // a diverged particle must not reach the GPU
    const float depth = -v.z();
    if (depth < near_limit || depth > far_limit) continue;
    if (std::abs(v.x()) > tan_x * depth + slack_x) continue;
    if (std::abs(v.y()) > tan_y * depth + slack_y) continue;
    // Silhouette bounds: the sphere's projected centre plus its projected radius taken at
    // its nearest depth (an over-estimate, which is all a bounding box needs).
    const float centre_x = half_w + focal * v.x() / depth;
    const float centre_y = half_h + focal * v.y() / depth;
    const float nearest = std::max(depth - radius, camera.near_clip);
    const float reach = focal * radius / nearest * (1.0f + std::abs(v.x() / depth) +
                                                   std::abs(v.y() / depth));
    nearest_centre = std::min(nearest_centre, depth);
    x_min = std::min(x_min, centre_x - reach);
    x_max = std::max(x_max, centre_x + reach);
    y_min = std::min(y_min, centre_y - reach);
    y_max = std::max(y_max, centre_y + reach);
    const Eigen::Vector4f texel(v.x(), v.y(), v.z(), 1.0f);
    if (split && (*neighbor_counts)[i] >= interior_neighbor_count)
      interior.push_back(texel);
    else
      out.view_positions.push_back(texel);
  }
  out.surface_count = out.view_positions.size();
  out.x_begin = out.y_begin = out.x_end = out.y_end = 0;
  out.nearest_depth = x_max >= x_min ? std::max(nearest_centre, camera.near_clip) : 0.0f;
  if (x_max >= x_min) {  // something is visible; pad by a pixel against rounding
    out.x_begin = std::clamp(static_cast<int>(std::floor(x_min)) - 1, 0, camera.width);
    out.x_end = std::clamp(static_cast<int>(std::ceil(x_max)) + 1, 0, camera.width);
    out.y_begin = std::clamp(static_cast<int>(std::floor(y_min)) - 1, 0, camera.height);
    out.y_end = std::clamp(static_cast<int>(std::ceil(y_max)) + 1, 0, camera.height);
  }
  out.view_positions.insert(out.view_positions.end(), interior.begin(), interior.end());
}

}  // namespace pbf
