#pragma once
// The kinetic-energy bounds a stress run must respect, and why.
//
// In a closed, static box the only energy source is gravity, and PBF (position projection,
// XSPH, the speed cap) only removes energy. So for any ordinary start the kinetic energy
// can never exceed the initial mechanical energy:
//   E_kin(t) <= E_kin,0 + E_pot,0                                       (physical bound)
// with E_pot measured from the lowest admissible particle centre (floor + d/2) under the
// case's own gravity (so gravity x 100 brings 100 x the budget, dt and iterations none).
//
// Starts with overlapping particles (all at one point, coincident, clamped in from outside
// the box) hold an arbitrarily compressed state: a stiff fluid has no finite energy for it,
// and the projection releases it as speed. Only the solver's speed cap bounds that:
//   E_kin(t) <= 1/2 N m cap^2,  cap = max_speed_factor sqrt(2 max(|g|, 9.81) L)  (cap bound)
// and the released energy must then be dissipated, not kept pumping: at the end of the run
//   E_kin(end) <= E_kin,0 + E_pot,0 + N m g H                            (settled bound)
// i.e. no more than the energy of lifting every particle by the container's height H.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "pbf_ros/core/FloatingBodies.h"
#include "pbf_ros/core/SolverParams.h"

namespace pbf_bench {

struct EnergyBound {
  double initial_kinetic = 0.0;
  double initial_potential = 0.0;  // relative to floor + d/2
  double overlap_allowance = 0.0;  // N m g H
  double speed_cap_bound = 0.0;    // 1/2 N m cap^2
  double physical() const { return initial_kinetic + initial_potential; }
  double settled() const { return physical() + overlap_allowance; }
};

// Floating bodies in the box can give the fluid their kinetic energy and the potential
// energy of sinking to the floor (centre no lower than the floor plus the body's smallest
// half extent), under the case's gravity. A body that rises takes energy from the fluid, so
// this is what the bodies can add at most:
//   E_kin(t) + E_kin,bodies(t) <= physical() + bodiesAllowance(...)
double bodiesAllowance(const pbf::FloatingBodies& bodies, const pbf::SolverParams& params,
                       const Eigen::AlignedBox3f& container);

// Positions outside the box count at the place the solver will clamp them to.
EnergyBound energyBound(const std::vector<Eigen::Vector3f>& positions,
                        const std::vector<Eigen::Vector3f>& velocities,
                        const pbf::SolverParams& params, const Eigen::AlignedBox3f& container);

}  // namespace pbf_bench
