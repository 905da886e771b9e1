// The fluid's force on solids (SolidWrench.h) against hydrostatics, in a resting tank with
// the shipped solver defaults: Archimedes on a held sphere and box, the side wall's
// rho0 g H^2 W / 2, and the container carrying the fluid's weight. Each case warms the tank
// up until it is at rest, then averages the force over time (weighted by each step's dt).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "SolverTestUtil.h"
#include "pbf_ros/core/Boundaries.h"
#include "pbf_ros/core/Metrics.h"

namespace {

constexpr double kPi = 3.14159265358979323846;

// A square tank `width` wide filled to `depth`; the shipped solver defaults but `spacing`.
// The wall case uses the default spacing (0.02 m: 0.3 m x 0.24 m, 2700 particles); the held
// solids a finer one (0.01 m in a 0.2 m tank, ~5k particles), so that they span 9-10
// particles: at 2.5 particles across a half-width the box's edges add +6 % (README).
constexpr float kWidth = 0.3f, kDepth = 0.24f;
pbf::Scene tank(const std::vector<pbf::Obstacle>& obstacles = {}, float width = kWidth,
                float depth = kDepth, float spacing = 0.02f) {
  pbf::Scene scene;
  scene.name = "wrench_tank";
  scene.container = Eigen::AlignedBox3f(Eigen::Vector3f::Zero(), Eigen::Vector3f(width, width, depth + 0.1f));
  pbf::FluidBlock block;
  block.min = Eigen::Vector3f::Zero();
  block.max = Eigen::Vector3f(width, width, depth);
  scene.fluid.push_back(block);
  scene.obstacles = obstacles;
  scene.solver.particle_spacing = spacing;
  return scene;
}

struct Averages {
  std::array<pbf::Wrench, 6> faces;
  pbf::Wrench container;
  std::vector<pbf::Wrench> obstacles;
  double seconds = 0.0;
  double level = 0.0;  // free surface height, averaged over the span [m]
  double weight = 0.0;  // of the fluid [N]
};

void addScaled(pbf::Wrench& sum, const pbf::Wrench& w, double s) {
  sum.force += s * w.force;
  sum.torque += s * w.torque;
}

// Warms the scene up for `warm` s (tracking off), then averages every solid's wrench over
// `span` s of simulated time.
Averages restingAverages(const pbf::Scene& scene, double warm, double span) {
  auto solver = pbf_test::makeSolver(scene);
  solver->advance(warm);
  // At rest: no bulk motion left (particles keep a small jitter, ~0.09 m/s rms, which is
  // the solver's at rest and what the averaging is for).
  const Eigen::Vector3d mean_velocity = pbf::velocitySum(solver->velocities()) / double(solver->size());
  EXPECT_LT(mean_velocity.norm(), 0.01) << "the tank is not at rest after the warm-up";
  solver->setWrenchTracking(true);
  Averages avg;
  avg.obstacles.resize(scene.obstacles.size());
  double level_sum = 0.0;
  int level_samples = 0;
  while (avg.seconds < span) {
    if (solver->stepCount() % 12 == 0) {  // the surface moves too: average it as well
      level_sum += pbf::freeSurfaceHeight(solver->positions(), scene.solver.particle_spacing, scene.container);
      ++level_samples;
    }
    const pbf::StepStats stats = solver->step();
    EXPECT_FALSE(stats.failed);
    const pbf::SolidWrenches& w = solver->wrenches();
    EXPECT_TRUE(w.valid);
    for (int f = 0; f < 6; ++f) addScaled(avg.faces[f], w.container_faces[f], stats.dt);
    addScaled(avg.container, w.container, stats.dt);
    for (std::size_t k = 0; k < w.obstacles.size(); ++k) addScaled(avg.obstacles[k], w.obstacles[k], stats.dt);
    avg.seconds += stats.dt;
  }
  const double inv = 1.0 / avg.seconds;
  for (auto& f : avg.faces) f.force *= inv, f.torque *= inv;
  avg.container.force *= inv, avg.container.torque *= inv;
  for (auto& o : avg.obstacles) o.force *= inv, o.torque *= inv;
  avg.level = level_sum / std::max(level_samples, 1);
  avg.weight = solver->size() * double(solver->params().particleMass()) * 9.81;
  return avg;
}

constexpr double kWarm = 1.0, kSpan = 0.5;  // [s]
constexpr double kRhoG = 1000.0 * 9.81;

TEST(SolidWrenches, OffByDefaultAndTrackingDoesNotChangeTheFluid) {
  pbf::Obstacle ball;
  ball.shape = pbf::Obstacle::Shape::Sphere;
  ball.radius = 0.06f;
  ball.pose.translation() = Eigen::Vector3f(0.15f, 0.15f, 0.12f);
  const pbf::Scene scene = tank({ball});
  auto plain = pbf_test::makeSolver(scene);
  auto tracked = pbf_test::makeSolver(scene);
  tracked->setWrenchTracking(true);
  auto largestDifference = [&] {
    float largest = 0.0f;
    for (std::size_t i = 0; i < plain->size(); ++i)
      largest = std::max(largest, (plain->positions()[i] - tracked->positions()[i]).norm());
    return largest;
  };
  plain->stepWith(1.0f / 240.0f);
  tracked->stepWith(1.0f / 240.0f);
  ASSERT_EQ(plain->size(), tracked->size());
  // Not bitwise: the compiler may contract the same projection into FMAs differently in its
  // tracked and untracked instantiations; one step differs by float rounding only.
  std::printf("largest difference tracked vs untracked after one step: %.3g m\n", largestDifference());
  EXPECT_LT(largestDifference(), 1e-6f);
  for (int s = 0; s < 20; ++s) {
    plain->stepWith(1.0f / 240.0f);
    tracked->stepWith(1.0f / 240.0f);
  }
  EXPECT_FALSE(plain->wrenches().valid);
  ASSERT_TRUE(tracked->wrenches().valid);
  // The fluid pushes the floor down and the ball up already while settling.
  EXPECT_LT(tracked->wrenches().container_faces[4].force.z(), 0.0);
  EXPECT_GT(tracked->wrenches().obstacles[0].force.z(), 0.0);
  tracked->setWrenchTracking(false);
  tracked->stepWith(1.0f / 240.0f);
  EXPECT_FALSE(tracked->wrenches().valid);
}

TEST(SolidWrenches, ContainerCarriesTheFluidsWeightAndSideWallsTheHydrostaticLoad) {
  const Averages a = restingAverages(tank(), kWarm, 2 * kSpan);  // cheap case: average longer
  const double wall = a.faces[1].force.x();  // the fluid pushes the +x wall outwards
  const double expected_wall = 0.5 * kRhoG * a.level * a.level * kWidth;
  std::printf("weight %.3f N, container %.3f %.3f %.3f N (%.3f %%)\n", a.weight,
              a.container.force.x(), a.container.force.y(), a.container.force.z(),
              100.0 * (-a.container.force.z() / a.weight - 1.0));
  std::printf("floor %.3f N; level %.4f m; +x wall %.3f N vs rho0 g H^2 W / 2 = %.3f N (%.2f %%); "
              "-x wall %.3f N, +y %.3f N, -y %.3f N\n",
              a.faces[4].force.z(), a.level, wall, expected_wall, 100.0 * (wall / expected_wall - 1.0),
              a.faces[0].force.x(), a.faces[3].force.y(), a.faces[2].force.y());
  EXPECT_NEAR(-a.container.force.z(), a.weight, 0.01 * a.weight);
  EXPECT_NEAR(a.container.force.head<2>().norm(), 0.0, 0.01 * a.weight);
  EXPECT_NEAR(wall, expected_wall, 0.03 * expected_wall);
  for (int f : {0, 2}) EXPECT_NEAR(-a.faces[f].force[f / 2], expected_wall, 0.03 * expected_wall) << "face " << f;
  EXPECT_NEAR(a.faces[3].force.y(), expected_wall, 0.03 * expected_wall);
}

void expectArchimedes(const pbf::Obstacle& o, double volume, const char* what) {
  const Averages a = restingAverages(tank({o}, 0.2f, 0.15f, 0.01f), kWarm, kSpan);
  const pbf::Wrench& w = a.obstacles[0];
  const double buoyancy = kRhoG * volume;
  std::printf("%s: F = (%.3f, %.3f, %.3f) N vs rho0 g V = %.3f N (%.2f %%), torque about its "
              "centre %.4f N m; level %.4f m\n",
              what, w.force.x(), w.force.y(), w.force.z(), buoyancy,
              100.0 * (w.force.z() / buoyancy - 1.0), w.torque.norm(), a.level);
  EXPECT_NEAR(w.force.z(), buoyancy, 0.03 * buoyancy) << what;
  EXPECT_NEAR(w.force.head<2>().norm(), 0.0, 0.03 * buoyancy) << what;
  // Symmetric about its centre: no torque worth the name (0.01 N x its size).
  EXPECT_LT(w.torque.norm(), 0.01 * buoyancy * 0.05) << what;
  // The fluid on the container and the solid together carry the fluid's weight.
  EXPECT_NEAR(-(a.container.force.z() + w.force.z()), a.weight, 0.01 * a.weight) << what;
}

// The Gauss-Seidel solve attributes the images' unbalanced push to the walls itself
// (GaussSeidelSweep.cpp): the same balance must hold.
TEST(SolidWrenches, GaussSeidelContainerCarriesTheFluidsWeight) {
  pbf::Scene scene = tank();
  scene.solver.gauss_seidel = true;
  scene.solver.min_iterations = 1;
  const Averages a = restingAverages(scene, kWarm, 2 * kSpan);
  std::printf("Gauss-Seidel: weight %.3f N, container %.3f %.3f %.3f N (%.3f %%)\n", a.weight,
              a.container.force.x(), a.container.force.y(), a.container.force.z(),
              100.0 * (-a.container.force.z() / a.weight - 1.0));
  EXPECT_NEAR(-a.container.force.z(), a.weight, 0.01 * a.weight);
  EXPECT_NEAR(a.container.force.head<2>().norm(), 0.0, 0.01 * a.weight);
  const double wall = a.faces[1].force.x();
  const double expected = 0.5 * kRhoG * a.level * a.level * kWidth;
  std::printf("Gauss-Seidel: +x wall %.3f N, rho0 g H^2 W / 2 %.3f N\n", wall, expected);
  EXPECT_NEAR(wall, expected, 0.03 * expected);
}

TEST(SolidWrenches, HeldSphereFeelsArchimedes) {
  pbf::Obstacle ball;
  ball.shape = pbf::Obstacle::Shape::Sphere;
  ball.radius = 0.045f;
  ball.pose.translation() = Eigen::Vector3f(0.1f, 0.1f, 0.07f);
  expectArchimedes(ball, 4.0 / 3.0 * kPi * std::pow(0.045, 3), "sphere R 4.5 cm");
}

TEST(SolidWrenches, HeldBoxFeelsArchimedes) {
  pbf::Obstacle box;
  box.shape = pbf::Obstacle::Shape::Box;
  // Faces halfway between lattice planes, as a scene's lattice leaves them.
  box.half_extents = Eigen::Vector3f(0.05f, 0.05f, 0.03f);
  box.pose.translation() = Eigen::Vector3f(0.1f, 0.1f, 0.065f);
  expectArchimedes(box, 0.10 * 0.10 * 0.06, "box 10 x 10 x 6 cm");
}

}  // namespace
