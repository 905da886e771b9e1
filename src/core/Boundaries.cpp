#include "pbf_ros/core/Boundaries.h"

namespace pbf {

SolidBoundaries::SolidBoundaries(const Eigen::AlignedBox3f& container,
                                 const Eigen::Isometry3f& container_pose,
                                 const std::vector<Obstacle>& obstacles, float support_radius,
                                 float particle_radius)
    : has_container_(!container.isEmpty()),
      posed_(!container_pose.isApprox(Eigen::Isometry3f::Identity(), 1e-7f)),
      box_(container),
      pose_(container_pose),
      inverse_(container_pose.inverse(Eigen::Isometry)),
      obstacles_(&obstacles),
      walls_(container, support_radius),
      h_(support_radius),
      radius_(particle_radius) {}

bool SolidBoundaries::density(const Eigen::Vector3f& p, float& fraction,
                              Eigen::Vector3f& gradient) const {
  bool near = false;
  if (has_container_) {
    if (!posed_) {
      near = walls_.accumulate(p, fraction, gradient);
    } else {
      Eigen::Vector3f g_local = Eigen::Vector3f::Zero();
      if (walls_.accumulate(inverse_ * p, fraction, g_local)) {
        gradient += pose_.linear() * g_local;
        near = true;
      }
    }
  }
  for (const Obstacle& o : *obstacles_) {
    if ((p - o.pose.translation()).squaredNorm() > std::pow(o.boundingRadius() + h_, 2.0f)) continue;
    Eigen::Vector3f n;
    const float s = std::max(o.signedDistance(p, n), 0.0f);
    if (s >= h_) continue;
    fraction += walls_.fractionBeyond(s);
    gradient -= walls_.planeMass(s) * n;  // density falls moving away along the normal
    near = true;
  }
  return near;
}

Eigen::Vector3f SolidBoundaries::project(const Eigen::Vector3f& p_in) const {
  Eigen::Vector3f p = p_in;
  for (const Obstacle& o : *obstacles_) {
    if ((p - o.pose.translation()).squaredNorm() > std::pow(o.boundingRadius() + radius_, 2.0f)) continue;
    Eigen::Vector3f n;
    const float s = o.signedDistance(p, n);
    if (s < radius_) p += (radius_ - s) * n;
  }
  if (has_container_) {
    const Eigen::Vector3f lo = box_.min() + Eigen::Vector3f::Constant(radius_);
    const Eigen::Vector3f hi = box_.max() - Eigen::Vector3f::Constant(radius_);
    if (!posed_) return p.cwiseMax(lo).cwiseMin(hi);
    return pose_ * (inverse_ * p).cwiseMax(lo).cwiseMin(hi);
  }
  return p;
}

bool SolidBoundaries::contact(const Eigen::Vector3f& p, Eigen::Vector3f& normal,
                              Eigen::Vector3f& surface_motion) const {
  const float touch = radius_ * 1.02f;
  for (std::size_t k = 0; k < obstacles_->size(); ++k) {
    const Obstacle& o = (*obstacles_)[k];
    if ((p - o.pose.translation()).squaredNorm() > std::pow(o.boundingRadius() + touch, 2.0f)) continue;
    if (o.signedDistance(p, normal) > touch) continue;
    surface_motion = Eigen::Vector3f::Zero();
    if (prev_obstacles_ && k < prev_obstacles_->size())  // where this surface point was
      surface_motion = p - (*prev_obstacles_)[k] * (o.pose.inverse(Eigen::Isometry) * p);
    return true;
  }
  if (!has_container_) return false;
  const Eigen::Vector3f q = posed_ ? Eigen::Vector3f(inverse_ * p) : p;
  for (int a = 0; a < 3; ++a) {
    Eigen::Vector3f n_local = Eigen::Vector3f::Zero();
    if (q[a] - box_.min()[a] <= touch) n_local[a] = 1.0f;
    else if (box_.max()[a] - q[a] <= touch) n_local[a] = -1.0f;
    else continue;
    normal = posed_ ? Eigen::Vector3f(pose_.linear() * n_local) : n_local;
    surface_motion = p - prev_container_ * q;
    return true;
  }
  return false;
}

}  // namespace pbf
