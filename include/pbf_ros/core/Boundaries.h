#pragma once
// Density the container's walls lend to particles near them.
//
// The seed only clamps escaped particles back into the box, so a particle near a wall
// misses the neighbours the wall cuts off: it is under-dense, and the fluid compacts
// against every wall (a settled tank ends ~10 % below the level its volume implies). Here
// each wall is treated as a half-space of virtual fluid at rest density -- the analytic
// limit of Akinci et al. (2012) boundary particles with psi = rho0 / sum W. For the Poly6
// kernel the fraction of the kernel beyond a plane at distance s has a closed form:
//   F(s) = (pi c / 4) * int_s^h (h^2 - z^2)^4 dz,   c = 315 / (64 pi h^9),
// so the wall adds rho0 F(s) to the density and -A(s) n to grad C, A(s) = (pi c/4)(h^2-s^2)^4.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "pbf_ros/core/Obstacle.h"

namespace pbf {

class BoxWallDensity {
 public:
  BoxWallDensity(const Eigen::AlignedBox3f& box, float support_radius)
      : box_(box),
        h_(support_radius),
        h2_(support_radius * support_radius),
        a_coef_(315.0f / (256.0f * std::pow(support_radius, 9.0f))),  // pi c / 4
        g_at_h_(primitive(support_radius)) {}

  // Adds the walls' density fraction (the sum of F over walls within h; dimensionless,
  // multiply by rho0) and its gradient with respect to the particle position.
  // Returns false, adding nothing, when no wall is within h: the common case.
  bool accumulate(const Eigen::Vector3f& p, float& fraction, Eigen::Vector3f& gradient) const {
    bool near = false;
    for (int a = 0; a < 3; ++a) {
      const float to_min = p[a] - box_.min()[a];  // wall normal +e_a
      if (to_min < h_) {
        const float s = std::max(to_min, 0.0f);
        fraction += fractionBeyond(s);
        gradient[a] -= planeMass(s);
        near = true;
      }
      const float to_max = box_.max()[a] - p[a];  // wall normal -e_a
      if (to_max < h_) {
        const float s = std::max(to_max, 0.0f);
        fraction += fractionBeyond(s);
        gradient[a] += planeMass(s);
        near = true;
      }
    }
    return near;
  }

  // F(s): fraction of the Poly6 kernel beyond a plane at distance s (0.5 at s = 0).
  float fractionBeyond(float s) const { return s >= h_ ? 0.0f : g_at_h_ - primitive(s); }
  // A(s) = -dF/ds: kernel mass per unit length in the plane at distance s.
  float planeMass(float s) const {
    if (s >= h_) return 0.0f;
    const float u = h2_ - s * s;
    return a_coef_ * (u * u) * (u * u);
  }

 private:
  // G(s) = (pi c / 4) int_0^s (h^2 - z^2)^4 dz, expanded.
  float primitive(float s) const {
    const float h2 = h2_, h4 = h2 * h2, h6 = h4 * h2, h8 = h4 * h4, s2 = s * s;
    return a_coef_ * s *
           (h8 - 4.0f / 3.0f * h6 * s2 + 6.0f / 5.0f * h4 * s2 * s2 -
            4.0f / 7.0f * h2 * s2 * s2 * s2 + s2 * s2 * s2 * s2 / 9.0f);
  }

  Eigen::AlignedBox3f box_;
  float h_, h2_, a_coef_, g_at_h_;
};

// Everything solid the fluid meets in one step: the container (a box with a pose in the
// fluid frame, moved by the node when it is attached to a tf frame) and the obstacles.
// Built once per pass from the solver's state; cheap to copy.
class SolidBoundaries {
 public:
  SolidBoundaries(const Eigen::AlignedBox3f& container, const Eigen::Isometry3f& container_pose,
                  const std::vector<Obstacle>& obstacles, float support_radius,
                  float particle_radius);

  // Density fraction (multiply by rho0) and its gradient lent by walls and obstacles
  // within h of p. Obstacles use the wall formula with their signed distance: exact for
  // flat faces, a close approximation where curvature radii exceed h. False: none near.
  bool density(const Eigen::Vector3f& p, float& fraction, Eigen::Vector3f& gradient) const;

  // p moved out of every obstacle and into the container, keeping particle_radius from
  // each surface. The container is applied last: no particle ever leaves it.
  Eigen::Vector3f project(const Eigen::Vector3f& p) const;

  // For a particle at p (after project): the unit normal of the surface it touches, if
  // any (within particle_radius plus a small tolerance), and how far that surface point
  // moved during the step (from the previous poses). Used for wall friction.
  bool contact(const Eigen::Vector3f& p, Eigen::Vector3f& normal,
               Eigen::Vector3f& surface_motion) const;

  // Poses at the start of the step, for surface_motion (default: not moving).
  void setPreviousPoses(const Eigen::Isometry3f& container,
                        const std::vector<Eigen::Isometry3f>* obstacles) {
    prev_container_ = container;
    prev_obstacles_ = obstacles;
  }

  bool hasContainer() const { return has_container_; }

 private:
  bool has_container_;
  bool posed_;  // container pose is not the identity
  Eigen::AlignedBox3f box_;
  Eigen::Isometry3f pose_, inverse_;
  const std::vector<Obstacle>* obstacles_;
  Eigen::Isometry3f prev_container_ = Eigen::Isometry3f::Identity();
  const std::vector<Eigen::Isometry3f>* prev_obstacles_ = nullptr;
  BoxWallDensity walls_;
  float h_, radius_;
};

}  // namespace pbf
