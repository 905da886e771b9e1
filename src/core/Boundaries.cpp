#include "pbf_ros/core/Boundaries.h"

#include <algorithm>
#include <cmath>

namespace pbf {

namespace {

// One axis of an axis-aligned box of ghost lattice points, written as a signed sum of
// half-lines: each term is a half-line beyond a plane at distance `arg` from the particle
// (LatticeBoundary::octant's argument), with a sign, and d arg / d q along the axis.
struct LineTerm {
  float arg, sign, slope;
};
struct AxisTerms {
  LineTerm term[3];
  int count = 0;
  void add(float arg, float sign, float slope) { term[count++] = {arg, sign, slope}; }
};

// sum over one term per axis of (product of signs) * T(args): the ghost sum over the
// product of the per-axis sets (inclusion-exclusion), and its gradient in the box frame.
void sumOctants(const LatticeBoundary& lattice, const AxisTerms (&axes)[3], float& value,
                Eigen::Vector3f& gradient) {
  value = 0.0f;
  gradient.setZero();
  for (int i = 0; i < axes[0].count; ++i)
    for (int j = 0; j < axes[1].count; ++j)
      for (int k = 0; k < axes[2].count; ++k) {
        const LineTerm* t[3] = {&axes[0].term[i], &axes[1].term[j], &axes[2].term[k]};
        float v;
        Eigen::Vector3f dv;
        if (!lattice.octant(Eigen::Vector3f(t[0]->arg, t[1]->arg, t[2]->arg), v, dv)) continue;
        const float sign = t[0]->sign * t[1]->sign * t[2]->sign;
        value += sign * v;
        for (int a = 0; a < 3; ++a) gradient[a] += sign * dv[a] * t[a]->slope;
      }
}

// What a convex surface with the given mean curvature radius lends less than a flat wall at
// the same distance s (<= 0): the continuum difference ball - half-space, added to the
// lattice-calibrated flat value. Added, not multiplied: the lattice's own discreteness sits
// in the nearest ghost layer straight behind the surface, which curvature barely changes;
// curvature takes away volume farther out, where the continuum is exact enough. (A ratio
// scaled that discreteness too and over-lent 1.3 % on the first layer of a sphere of radius
// 2h; the sum lends within 0.5 %, test_calibration.) d/ds by a central difference.
float curvatureCorrection(float s, float radius, float h, float& d_ds) {
  auto missing = [&](double t) {
    t = std::max(t, 0.0);
    return continuumBallFraction(t, radius, h) - continuumHalfSpaceFraction(t, h);
  };
  const double e = 1e-3 * h;
  d_ds = static_cast<float>((missing(s + e) - missing(s - e)) / (2.0 * e));
  return static_cast<float>(missing(s));
}

}  // namespace

SolidBoundaries::SolidBoundaries(const Eigen::AlignedBox3f& container,
                                 const Eigen::Isometry3f& container_pose,
                                 const std::vector<Obstacle>& obstacles,
                                 const LatticeBoundary& lattice, float particle_radius)
    : has_container_(!container.isEmpty()),
      posed_(!container_pose.isApprox(Eigen::Isometry3f::Identity(), 1e-7f)),
      box_(container),
      pose_(container_pose),
      inverse_(container_pose.inverse(Eigen::Isometry)),
      obstacles_(&obstacles),
      lattice_(&lattice),
      reach_(lattice.reach()),
      radius_(particle_radius) {
  lowest_ = box_.min() + Eigen::Vector3f::Constant(radius_);
  highest_ = box_.max() - Eigen::Vector3f::Constant(radius_);
  near_.resize(obstacles.size());
  for (std::size_t k = 0; k < near_.size(); ++k) near_[k] = static_cast<std::uint32_t>(k);
}

void SolidBoundaries::keepOnlyObstaclesNear(const Eigen::AlignedBox3f& fluid) {
  near_.clear();
  for (std::size_t k = 0; k < obstacles_->size(); ++k) {
    const Obstacle& o = (*obstacles_)[k];
    // The farthest any per-particle test looks: density within the kernel's reach,
    // projection within the particle radius, friction contact within a spacing.
    const float r = o.boundingRadius() + std::max(reach_, 2.0f * radius_);
    if (fluid.squaredExteriorDistance(o.pose.translation()) <= r * r) near_.push_back(static_cast<std::uint32_t>(k));
  }
}

bool SolidBoundaries::densityNearObstacles(const Eigen::Vector3f& p, float& fraction,
                                           Eigen::Vector3f& gradient) const {
  bool near = false;
  for (const std::uint32_t k : near_) {
    const Obstacle& o = (*obstacles_)[k];
    if ((p - o.pose.translation()).squaredNorm() > std::pow(o.boundingRadius() + reach_, 2.0f)) continue;
    const bool hit = o.shape == Obstacle::Shape::Box ? boxDensity(o, p, fraction, gradient)
                                                      : curvedDensity(o, p, fraction, gradient);
    near = near || hit;
  }
  return near;
}

// A box obstacle is ghost fluid inside it: per axis, the half-line beyond the near face
// minus the half-line beyond the far face (which matters for plates thinner than h).
bool SolidBoundaries::boxDensity(const Obstacle& o, const Eigen::Vector3f& p, float& fraction,
                                 Eigen::Vector3f& gradient) const {
  const Eigen::Vector3f q = o.pose.inverse(Eigen::Isometry) * p;
  const float d = lattice_->spacing();
  AxisTerms axes[3];
  for (int a = 0; a < 3; ++a) {
    const float sign = q[a] < 0.0f ? -1.0f : 1.0f;
    const float near_face = std::abs(q[a]) - o.half_extents[a];
    if (near_face >= reach_) return false;
    axes[a].add(near_face, 1.0f, sign);
    const float layers = std::max(1.0f, std::round(2.0f * o.half_extents[a] / d));
    if (near_face + layers * d < reach_) axes[a].add(near_face + layers * d, -1.0f, sign);
  }
  float f;
  Eigen::Vector3f g;
  sumOctants(*lattice_, axes, f, g);
  if (f == 0.0f) return false;
  fraction += f;
  gradient += o.pose.linear() * g;
  return true;
}

// Spheres and capsules (and any other shape, by its signed distance): the flat-wall lattice
// fraction at the distance s, less what the surface's curvature takes away. A capsule's side
// is a cylinder, whose mean curvature is that of a sphere of twice its radius; towards the
// ends it blends into the hemispheres' over one support radius, so there is no jump.
bool SolidBoundaries::curvedDensity(const Obstacle& o, const Eigen::Vector3f& p, float& fraction,
                                    Eigen::Vector3f& gradient) const {
  Eigen::Vector3f n;
  const float s = o.signedDistance(p, n);
  if (s >= reach_) return false;
  float dflat;
  const float flat = lattice_->halfSpace(s, dflat);
  float curved = 0.0f, dcurved = 0.0f;
  if (o.shape == Obstacle::Shape::Sphere || o.shape == Obstacle::Shape::Capsule) {
    float mean_radius = o.radius;
    if (o.shape == Obstacle::Shape::Capsule) {
      const float z = std::abs((o.pose.inverse(Eigen::Isometry) * p).z());
      const float inward = std::clamp((o.half_length - z) / lattice_->reach(), 0.0f, 1.0f);
      mean_radius = o.radius / (1.0f - 0.5f * inward);
    }
    curved = curvatureCorrection(s, mean_radius, lattice_->supportRadius(), dcurved);
  }
  fraction += flat + curved;
  gradient += (dflat + dcurved) * n;
  return true;
}

bool SolidBoundaries::contact(const Eigen::Vector3f& p, float reach, Eigen::Vector3f& normal,
                              Eigen::Vector3f& surface_motion, int* solid) const {
  for (const std::uint32_t k : near_) {
    const Obstacle& o = (*obstacles_)[k];
    if ((p - o.pose.translation()).squaredNorm() > std::pow(o.boundingRadius() + reach, 2.0f)) continue;
    if (o.signedDistance(p, normal) > reach) continue;
    surface_motion = Eigen::Vector3f::Zero();
    if (prev_obstacles_ && k < prev_obstacles_->size())  // where this surface point was
      surface_motion = p - (*prev_obstacles_)[k] * (o.pose.inverse(Eigen::Isometry) * p);
    if (solid) *solid = kContainerFaces + static_cast<int>(k);
    return true;
  }
  if (!has_container_) return false;
  const Eigen::Vector3f q = posed_ ? Eigen::Vector3f(inverse_ * p) : p;
  for (int a = 0; a < 3; ++a) {
    Eigen::Vector3f n_local = Eigen::Vector3f::Zero();
    if (q[a] - box_.min()[a] <= reach) n_local[a] = 1.0f;
    else if (box_.max()[a] - q[a] <= reach) n_local[a] = -1.0f;
    else continue;
    if (solid) *solid = 2 * a + (n_local[a] > 0.0f ? 0 : 1);
    normal = posed_ ? Eigen::Vector3f(pose_.linear() * n_local) : n_local;
    surface_motion = p - prev_container_ * q;
    return true;
  }
  return false;
}

}  // namespace pbf
