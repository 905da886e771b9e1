#pragma once
// Puts a scene into a solver: parameters, container, obstacles and the initial particles.
// The one place that knows how a Scene maps onto a PbfSolver (node, tools and tests).

#include "pbf_ros/core/PbfSolver.h"
#include "pbf_ros/core/Scene.h"

namespace pbf {

// Throws std::invalid_argument (from the solver) for unusable values; the solver is then
// left as it was only if the failure came from the parameters (checked first).
inline void setUpSolver(const Scene& scene, PbfSolver& solver) {
  solver.setParams(scene.solver);
  std::vector<Eigen::Vector3f> x, v;
  scene.initialParticles(x, v);
  solver.setContainer(scene.container);
  solver.setContainerPose(Eigen::Isometry3f::Identity());
  solver.setObstacles(scene.obstacles);
  solver.setParticles(x, v);
}

}  // namespace pbf
