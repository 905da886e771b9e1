#include "pbf_ros/core/FloatingBodies.h"

namespace pbf {

std::size_t FloatingBodies::afterStep(PbfSolver& solver, double dt) {
  const SolidWrenches& wrenches = solver.wrenches();
  if (!wrenches.valid || !(dt > 0.0)) return 0;
  const Eigen::Vector3d gravity = solver.params().gravity.cast<double>();
  const double max_speed = solver.maxSpeedCap();
  std::size_t stuck = 0;
  for (auto& [index, body] : bodies_) {
    if (index >= wrenches.obstacles.size()) continue;
    const Wrench& fluid = wrenches.obstacles[index];
    // A non-finite wrench (a rejected state cannot give one, but be sure) moves nothing.
    if (!body.step(fluid.allFinite() ? fluid : Wrench(), gravity, dt, max_speed)) ++stuck;
    if (!solver.container().isEmpty()) body.collide(solver.container(), solver.containerPose());
    solver.setObstaclePose(index, body.shape().pose);
  }
  return stuck;
}

FloatingBodies makeFloatingBodies(const Scene& scene) {
  FloatingBodies bodies;
  for (const FloatingBodySpec& f : scene.floating)
    if (f.obstacle < scene.obstacles.size())
      bodies.add(f.obstacle, RigidBody(scene.obstacles[f.obstacle], f.mass, f.inertia));
  return bodies;
}

}  // namespace pbf
