#pragma once
// Helpers shared by the solver tests: load a scene from the source tree, build a solver.

#include <memory>
#include <string>

#include "pbf_ros/core/PbfSolver.h"
#include "pbf_ros/core/Scene.h"
#include "pbf_ros/core/SceneSetup.h"

namespace pbf_test {

inline pbf::Scene loadScene(const std::string& name) {
  return pbf::loadSceneFile(std::string(PBF_SOURCE_DIR) + "/config/scenes/" + name + ".yaml");
}

inline std::unique_ptr<pbf::PbfSolver> makeSolver(const pbf::Scene& scene) {
  auto solver = std::make_unique<pbf::PbfSolver>();
  pbf::setUpSolver(scene, *solver);
  return solver;
}

// The level a settled fluid's mass implies over the container's floor, at rho0 [m].
inline double impliedLevel(const pbf::PbfSolver& solver, const pbf::Scene& scene) {
  const Eigen::Vector2f floor = scene.container.sizes().head<2>();
  return solver.size() * scene.solver.particleMass() / scene.solver.rest_density / (floor.x() * floor.y());
}

// Positions in the order the particles were given (the solver keeps them sorted by cell).
inline std::vector<Eigen::Vector3f> positionsById(const pbf::PbfSolver& s) {
  std::vector<Eigen::Vector3f> out(s.size());
  for (std::size_t k = 0; k < s.size(); ++k) out[s.ids()[k]] = s.positions()[k];
  return out;
}

}  // namespace pbf_test
