#include "pbf_ros/core/SolidWrench.h"

#include <algorithm>

#include "pbf_ros/core/Obstacle.h"

namespace pbf {

void WrenchAccumulator::reset(std::size_t solids, int threads) {
  solids_ = solids;
  threads_ = std::max(threads, 1);
  // Threads write their own blocks; 8 solids x 6 doubles = 6 cache lines: no false sharing.
  stride_ = (solids + 7) / 8 * 8;
  sums_.assign(static_cast<std::size_t>(threads_) * stride_ * 6, 0.0);
}

SolidWrenches WrenchAccumulator::result(double mass, double dt,
                                        const Eigen::Vector3d& container_origin,
                                        const std::vector<Obstacle>& obstacles) const {
  SolidWrenches out;
  out.valid = true;
  out.obstacles.resize(obstacles.size());
  const double scale = -mass / (dt * dt);  // the solid feels the reaction
  for (std::size_t s = 0; s < solids_; ++s) {
    Eigen::Vector3d dx = Eigen::Vector3d::Zero(), moment = Eigen::Vector3d::Zero();
    for (int t = 0; t < threads_; ++t) {
      const double* v = &sums_[(static_cast<std::size_t>(t) * stride_ + s) * 6];
      dx += Eigen::Vector3d(v[0], v[1], v[2]);
      moment += Eigen::Vector3d(v[3], v[4], v[5]);
    }
    const bool face = s < out.container_faces.size();
    if (!face && s - out.container_faces.size() >= obstacles.size()) break;
    const Eigen::Vector3d origin =
        face ? container_origin
             : obstacles[s - out.container_faces.size()].pose.translation().cast<double>();
    Wrench w;
    w.force = scale * dx;
    w.torque = scale * (moment - origin.cross(dx));  // sum (x - o) x dx
    if (face)
      out.container_faces[s] = w;
    else
      out.obstacles[s - out.container_faces.size()] = w;
  }
  for (const Wrench& f : out.container_faces) out.container += f;
  return out;
}

}  // namespace pbf
