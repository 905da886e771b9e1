#pragma once
// Two-way coupling of rigid bodies (RigidBody.h) with a PbfSolver: each body is one of the
// solver's obstacles. After every solver step the bodies move under the wrench the fluid
// put on them in that step, gravity and container contact, and the solver gets their new
// poses (the walls of a moving obstacle push the fluid in the next step). The solver must
// measure wrenches while there are bodies: prepare() turns that on.

#include <cstddef>
#include <utility>
#include <vector>

#include "pbf_ros/core/PbfSolver.h"
#include "pbf_ros/core/RigidBody.h"
#include "pbf_ros/core/Scene.h"

namespace pbf {

class FloatingBodies {
 public:
  // `obstacle` indexes the solver's obstacles; the body starts at that obstacle's pose.
  void add(std::size_t obstacle, RigidBody body) { bodies_.emplace_back(obstacle, std::move(body)); }
  bool empty() const { return bodies_.empty(); }
  const std::vector<std::pair<std::size_t, RigidBody>>& bodies() const { return bodies_; }

  // Before a step: wrenches are measured when there are bodies.
  void prepare(PbfSolver& solver) const {
    if (!bodies_.empty()) solver.setWrenchTracking(true);
  }
  // After a step of `dt` (nothing happens after a failed step). Bodies move at most at the
  // solver's speed cap (PbfSolver::maxSpeedCap). Returns how many bodies could not move
  // because their step overflowed (they stay, at rest; RigidBody::step).
  std::size_t afterStep(PbfSolver& solver, double dt);

 private:
  std::vector<std::pair<std::size_t, RigidBody>> bodies_;
};

// The bodies a scene's `dynamic` obstacles describe, at their obstacles' poses. Throws
// std::invalid_argument for an unusable mass or inertia.
FloatingBodies makeFloatingBodies(const Scene& scene);

}  // namespace pbf
