#include "pbf_ros/core/Obstacle.h"

#include <cmath>
#include <sstream>

namespace pbf {

namespace {

// Box centred at the origin: exact signed distance and outward normal.
float boxDistance(const Eigen::Vector3f& q, const Eigen::Vector3f& half, Eigen::Vector3f& n) {
  const Eigen::Vector3f d = q.cwiseAbs() - half;
  const Eigen::Vector3f sign = q.unaryExpr([](float v) { return v < 0.0f ? -1.0f : 1.0f; });
  if ((d.array() > 0.0f).any()) {  // outside: distance to the closest point
    const Eigen::Vector3f out = d.cwiseMax(0.0f);
    const float len = out.norm();
    n = out.cwiseProduct(sign) / len;
    return len;
  }
  int axis = 0;  // inside: leave through the nearest face
  d.maxCoeff(&axis);
  n = Eigen::Vector3f::Zero();
  n[axis] = sign[axis];
  return d[axis];
}

}  // namespace

float Obstacle::signedDistance(const Eigen::Vector3f& p, Eigen::Vector3f& normal) const {
  const Eigen::Vector3f q = pose.inverse(Eigen::Isometry) * p;  // local coordinates
  Eigen::Vector3f n_local;
  float dist = 0.0f;
  switch (shape) {
    case Shape::Box:
      dist = boxDistance(q, half_extents, n_local);
      break;
    case Shape::Sphere:
    case Shape::Capsule: {
      Eigen::Vector3f axis_point = Eigen::Vector3f::Zero();
      if (shape == Shape::Capsule) axis_point.z() = std::clamp(q.z(), -half_length, half_length);
      const Eigen::Vector3f r = q - axis_point;
      const float len = r.norm();
      // At the exact centre any direction is valid: pick +z.
      n_local = len > 1e-12f ? Eigen::Vector3f(r / len) : Eigen::Vector3f::UnitZ();
      dist = len - radius;
      break;
    }
  }
  normal = pose.linear() * n_local;
  return dist;
}

float Obstacle::boundingRadius() const {
  switch (shape) {
    case Shape::Box: return half_extents.norm();
    case Shape::Sphere: return radius;
    case Shape::Capsule: return radius + half_length;
  }
  return 0.0f;
}

std::string Obstacle::validate() const {
  std::ostringstream err;
  if (shape == Shape::Box && !(half_extents.allFinite() && (half_extents.array() > 0.0f).all()))
    err << "box half_extents must be finite and > 0";
  else if (shape != Shape::Box && !(std::isfinite(radius) && radius > 0.0f))
    err << "radius must be finite and > 0";
  else if (shape == Shape::Capsule && !(std::isfinite(half_length) && half_length >= 0.0f))
    err << "capsule half_length must be finite and >= 0";
  else if (!pose.matrix().allFinite() || !offset.matrix().allFinite())
    err << "pose must be finite";
  return err.str();
}

}  // namespace pbf
