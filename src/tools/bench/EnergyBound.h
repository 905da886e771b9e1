#pragma once
// The kinetic-energy bound a stress run must respect, and why.
//
// In a closed, static box the only energy source is gravity, and PBF (position projection,
// XSPH) only removes energy. So the kinetic energy can never exceed the initial mechanical
// energy: E_kin,0 + E_pot,0, with E_pot measured from the lowest admissible particle centre
// (floor + d/2) under the case's own gravity (so gravity x 100 brings 100 x the budget).
// Hostile starts (particles coincident, at one point, outside the box) store energy in the
// initial overlap that the projection releases; we allow for that once, as the work needed
// to lift every particle by the container's full height: N m g H. That allowance is about
// 16x tighter than what the solver's speed cap alone guarantees (1/2 N m cap^2, cap =
// 4 sqrt(2 g L)), so a run that gains energy from nowhere fails this check long before the
// cap hides it.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "pbf_ros/core/SolverParams.h"

namespace pbf_bench {

struct EnergyBound {
  double initial_kinetic = 0.0;
  double initial_potential = 0.0;  // relative to floor + d/2
  double overlap_allowance = 0.0;  // N m g H
  double speed_cap_bound = 0.0;    // 1/2 N m cap^2 (for reference)
  double bound() const { return initial_kinetic + initial_potential + overlap_allowance; }
};

// Positions outside the box count at the place the solver will clamp them to.
EnergyBound energyBound(const std::vector<Eigen::Vector3f>& positions,
                        const std::vector<Eigen::Vector3f>& velocities,
                        const pbf::SolverParams& params, const Eigen::AlignedBox3f& container);

}  // namespace pbf_bench
