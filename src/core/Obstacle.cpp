#include "pbf_ros/core/Obstacle.h"

#include <algorithm>
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

// Cylinder along z centred at the origin, flat caps: exact signed distance and outward
// normal. Outside, the closest point is on the side, a cap, or the rim between them;
// inside, the nearer of the side and the caps.
float cylinderDistance(const Eigen::Vector3f& q, float radius, float half_length, Eigen::Vector3f& n) {
  const float r = std::hypot(q.x(), q.y());
  // On the axis any radial direction is valid: pick +x.
  const Eigen::Vector3f radial = r > 1e-12f ? Eigen::Vector3f(q.x() / r, q.y() / r, 0.0f)
                                            : Eigen::Vector3f::UnitX();
  const Eigen::Vector3f axial(0.0f, 0.0f, q.z() < 0.0f ? -1.0f : 1.0f);
  const float to_side = r - radius, to_cap = std::abs(q.z()) - half_length;
  if (to_side > 0.0f && to_cap > 0.0f) {  // beyond the rim
    const float len = std::hypot(to_side, to_cap);
    n = (to_side * radial + to_cap * axial) / len;
    return len;
  }
  if (to_side > to_cap) {
    n = radial;
    return to_side;
  }
  n = axial;
  return to_cap;
}

}  // namespace

float Obstacle::signedDistance(const Eigen::Vector3f& p, Eigen::Vector3f& normal) const {
  const Eigen::Vector3f q = pose.inverse(Eigen::Isometry) * p;  // local coordinates
  Eigen::Vector3f n_local = Eigen::Vector3f::UnitZ();
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
    case Shape::Cylinder:
      dist = cylinderDistance(q, radius, half_length, n_local);
      break;
    case Shape::Mesh:
      dist = sdf->signedDistance(q, n_local);
      break;
  }
  normal = pose.linear() * n_local;
  return dist;
}

float Obstacle::boundingRadius() const {
  switch (shape) {
    case Shape::Box: return half_extents.norm();
    case Shape::Sphere: return radius;
    case Shape::Capsule: return radius + half_length;
    case Shape::Cylinder: return std::hypot(radius, half_length);
    case Shape::Mesh: return sdf ? sdf->boundingRadius() : 0.0f;
  }
  return 0.0f;
}

Eigen::Vector3f Obstacle::localHalfExtents() const {
  switch (shape) {
    case Shape::Box: return half_extents;
    case Shape::Sphere: return Eigen::Vector3f::Constant(radius);
    case Shape::Capsule: return Eigen::Vector3f(radius, radius, half_length + radius);
    case Shape::Cylinder: return Eigen::Vector3f(radius, radius, half_length);
    case Shape::Mesh: break;
  }
  return Eigen::Vector3f::Constant(boundingRadius());
}

std::string Obstacle::validate() const {
  std::ostringstream err;
  const bool round = shape == Shape::Sphere || shape == Shape::Capsule || shape == Shape::Cylinder;
  if (shape == Shape::Box && !(half_extents.allFinite() && (half_extents.array() > 0.0f).all()))
    err << "box half_extents must be finite and > 0";
  else if (round && !(std::isfinite(radius) && radius > 0.0f))
    err << "radius must be finite and > 0";
  else if (shape == Shape::Capsule && !(std::isfinite(half_length) && half_length >= 0.0f))
    err << "capsule half_length must be finite and >= 0";
  else if (shape == Shape::Cylinder && !(std::isfinite(half_length) && half_length > 0.0f))
    err << "cylinder half_length must be finite and > 0";
  else if (shape == Shape::Mesh && !sdf)
    err << "mesh obstacle has no signed distance grid (build one from its triangles)";
  else if (!pose.matrix().allFinite() || !offset.matrix().allFinite())
    err << "pose must be finite";
  return err.str();
}

}  // namespace pbf
