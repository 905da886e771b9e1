#include "pbf_ros/core/Metrics.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace pbf {

double meanHeightAboveFloor(const std::vector<Eigen::Vector3f>& positions, const Eigen::AlignedBox3f& container) {
  double z = 0.0;
  for (const auto& p : positions) z += p.z() - container.min().z();
  return z / static_cast<double>(std::max<std::size_t>(positions.size(), 1));
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
