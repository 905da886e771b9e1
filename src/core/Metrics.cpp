#include "pbf_ros/core/Metrics.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace pbf {

double freeSurfaceHeight(const std::vector<Eigen::Vector3f>& positions, float spacing,
                         const Eigen::AlignedBox3f& container) {
  const float w = 2.0f * spacing;
  const Eigen::Vector3f lo = container.min();
  const int nx = std::max(1, static_cast<int>(std::floor(container.sizes().x() / w)));
  const int ny = std::max(1, static_cast<int>(std::floor(container.sizes().y() / w)));
  std::vector<float> top(static_cast<std::size_t>(nx) * ny, -INFINITY);
  for (const auto& p : positions) {
    const int ix = std::clamp(static_cast<int>((p.x() - lo.x()) / w), 0, nx - 1);
    const int iy = std::clamp(static_cast<int>((p.y() - lo.y()) / w), 0, ny - 1);
    float& t = top[static_cast<std::size_t>(iy) * nx + ix];
    t = std::max(t, p.z());
  }
  std::vector<float> interior;
  for (int iy = 0; iy < ny; ++iy)
    for (int ix = 0; ix < nx; ++ix) {
      const bool wall = ix == 0 || iy == 0 || ix == nx - 1 || iy == ny - 1;
      const float t = top[static_cast<std::size_t>(iy) * nx + ix];
      if ((!wall || nx <= 2 || ny <= 2) && std::isfinite(t)) interior.push_back(t);
    }
  if (interior.empty()) return 0.0;
  std::nth_element(interior.begin(), interior.begin() + interior.size() / 2, interior.end());
  return interior[interior.size() / 2] + 0.5 * spacing - lo.z();
}

std::size_t countOutside(const std::vector<Eigen::Vector3f>& positions,
                         const Eigen::AlignedBox3f& box, float tolerance) {
  const Eigen::Vector3f lo = box.min() - Eigen::Vector3f::Constant(tolerance);
  const Eigen::Vector3f hi = box.max() + Eigen::Vector3f::Constant(tolerance);
  return static_cast<std::size_t>(std::count_if(positions.begin(), positions.end(), [&](const auto& p) {
    return !((p.array() >= lo.array()).all() && (p.array() <= hi.array()).all());
  }));
}

bool allFinite(const std::vector<Eigen::Vector3f>& values) {
  return std::all_of(values.begin(), values.end(), [](const auto& v) { return v.allFinite(); });
}

Eigen::Vector3d velocitySum(const std::vector<Eigen::Vector3f>& velocities) {
  Eigen::Vector3d s = Eigen::Vector3d::Zero();
  for (const auto& v : velocities) s += v.cast<double>();
  return s;
}

}  // namespace pbf
