// Floating bodies (RigidBody.h, FloatingBodies.h): obstacles the fluid moves, two-way
// coupled through the measured wrench. Shipped solver defaults but the spacing.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "SolverTestUtil.h"
#include "pbf_ros/core/FloatingBodies.h"
#include "pbf_ros/core/Metrics.h"

namespace {

constexpr float kSpacing = 0.0125f;

pbf::Scene tank(float width, float depth, const pbf::Obstacle& body) {
  pbf::Scene scene;
  scene.name = "floating";
  scene.container = Eigen::AlignedBox3f(Eigen::Vector3f::Zero(), Eigen::Vector3f(width, width, depth + 0.15f));
  pbf::FluidBlock block;
  block.max = Eigen::Vector3f(width, width, depth);
  scene.fluid.push_back(block);
  scene.obstacles = {body};
  scene.solver.particle_spacing = kSpacing;
  return scene;
}

// Median free-surface height over the columns (2 spacings wide) away from the body's footprint.
double levelAwayFrom(const pbf::PbfSolver& s, const Eigen::Vector3f& centre, float half_width) {
  std::map<std::pair<int, int>, float> top;
  for (const auto& p : s.positions()) {
    if (std::abs(p.x() - centre.x()) < half_width + 2 * kSpacing &&
        std::abs(p.y() - centre.y()) < half_width + 2 * kSpacing)
      continue;
    const auto key = std::make_pair(int(p.x() / (2 * kSpacing)), int(p.y() / (2 * kSpacing)));
    auto it = top.find(key);
    if (it == top.end() || it->second < p.z()) top[key] = p.z();
  }
  std::vector<float> tops;
  for (const auto& kv : top) tops.push_back(kv.second + 0.5f * kSpacing);
  std::nth_element(tops.begin(), tops.begin() + tops.size() / 2, tops.end());
  return tops[tops.size() / 2];
}

struct Coupled {
  std::unique_ptr<pbf::PbfSolver> solver;
  pbf::FloatingBodies bodies;
};

Coupled start(const pbf::Scene& scene, double density) {
  Coupled run;
  run.solver = pbf_test::makeSolver(scene);
  const pbf::Obstacle& o = scene.obstacles[0];
  const double mass = density * pbf::solidVolume(o);
  run.bodies.add(0, pbf::RigidBody(o, mass, pbf::solidInertia(o, mass)));
  return run;
}

void step(Coupled& run) {
  run.bodies.prepare(*run.solver);
  const pbf::StepStats stats = run.solver->step();
  ASSERT_FALSE(stats.failed);
  run.bodies.afterStep(*run.solver, stats.dt);
}

const pbf::RigidBody& body(const Coupled& run) { return run.bodies.bodies()[0].second; }

TEST(FloatingBodies, BoxOfHalfTheWatersDensityFloatsHalfSubmerged) {
  // 16 x 16 x 10 cm, 500 kg/m^3, starting where it should float, in a 25 cm tank.
  pbf::Obstacle box;
  box.shape = pbf::Obstacle::Shape::Box;
  box.half_extents = Eigen::Vector3f(0.08f, 0.08f, 0.05f);
  box.pose.translation() = Eigen::Vector3f(0.125f, 0.125f, 0.15f);
  const pbf::Scene scene = tank(0.25f, 0.15f, box);
  Coupled run = start(scene, 500.0);
  double bottom = 0.0, seconds = 0.0, tilt = 0.0;
  while (run.solver->time() < 1.2) {
    step(run);
    const Eigen::Isometry3f& pose = body(run).shape().pose;
    tilt = std::max(tilt, double(Eigen::AngleAxisf(pose.linear()).angle()));
    if (run.solver->time() > 0.8) {
      const double dt = run.solver->time() - (seconds > 0.0 ? 0.8 + seconds : 0.8);
      bottom += dt * (pose.translation().z() - 0.05);
      seconds += dt;
    }
  }
  bottom /= seconds;
  // The water line two ways: the free surface measured away from the box (its top particles
  // + d/2), and the level the fluid's mass implies at rho0 with the box's submerged volume.
  const double measured = levelAwayFrom(*run.solver, box.pose.translation(), 0.08f);
  const double fluid_volume = run.solver->size() * std::pow(kSpacing, 3);  // m / rho0
  const double tank_area = 0.25 * 0.25, box_area = 0.16 * 0.16;
  const double implied_draft = (fluid_volume / tank_area - bottom) / (1.0 - box_area / tank_area);
  const double measured_draft = measured - bottom;
  std::printf("box bottom %.4f m; draft below the measured surface (%.4f m) %.4f m (%+.1f %%), "
              "below the mass-implied level %.4f m (%+.1f %%); expected 0.05 m; largest tilt %.3f rad\n",
              bottom, measured, measured_draft, 100.0 * (measured_draft / 0.05 - 1.0), implied_draft,
              100.0 * (implied_draft / 0.05 - 1.0), tilt);
  EXPECT_NEAR(implied_draft, 0.05, 0.05 * 0.05);
  // The measured surface: 0.3 mm below the implied level with the free surface lent
  // (doc/calibration.md), ~0.2 spacings below it without.
  EXPECT_NEAR(measured_draft, 0.05, 0.08 * 0.05);
  EXPECT_LT(tilt, 0.1);  // a flat box of this density floats flat
}

TEST(FloatingBodies, DenserBodySinksToTheFloorAndStays) {
  pbf::Obstacle ball;
  ball.shape = pbf::Obstacle::Shape::Sphere;
  ball.radius = 0.03f;
  ball.pose.translation() = Eigen::Vector3f(0.1f, 0.1f, 0.08f);
  Coupled run = start(tank(0.2f, 0.12f, ball), 2000.0);
  while (run.solver->time() < 1.0) step(run);
  const double z = body(run).shape().pose.translation().z();
  const double speed = body(run).linearVelocity().norm();
  std::printf("dense ball: centre at %.4f m (radius 0.03), speed %.4f m/s\n", z, speed);
  EXPECT_NEAR(z, 0.03, 0.003);
  EXPECT_LT(speed, 0.02);
  while (run.solver->time() < 1.3) step(run);
  EXPECT_NEAR(body(run).shape().pose.translation().z(), 0.03, 0.003) << "it stays";
}

// Total energy of fluid and body: kinetic plus potential (z up, g = 9.81).
double energy(const Coupled& run) {
  const pbf::PbfSolver& s = *run.solver;
  const double m = s.params().particleMass(), g = -s.params().gravity.z();
  double e = 0.0;
  for (std::size_t i = 0; i < s.size(); ++i)
    e += 0.5 * m * s.velocities()[i].squaredNorm() + m * g * s.positions()[i].z();
  return e + body(run).kineticEnergy() + body(run).mass() * g * body(run).shape().pose.translation().z();
}

TEST(FloatingBodies, DroppedBallBobsComesToRestAndMakesNoEnergy) {
  pbf::Obstacle ball;
  ball.shape = pbf::Obstacle::Shape::Sphere;
  ball.radius = 0.03f;
  ball.pose.translation() = Eigen::Vector3f(0.1f, 0.1f, 0.17f);  // 5 cm above the water
  Coupled run = start(tank(0.2f, 0.12f, ball), 500.0);
  const double drop = body(run).mass() * 9.81 * 0.05;
  const double e0 = energy(run);
  double gain = 0.0, lowest = 1.0;
  while (run.solver->time() < 1.5) {
    step(run);
    gain = std::max(gain, energy(run) - e0);
    lowest = std::min(lowest, double(body(run).shape().pose.translation().z()));
  }
  const double z = body(run).shape().pose.translation().z();
  const double level = levelAwayFrom(*run.solver, ball.pose.translation(), 0.03f);
  std::printf("dropped ball: dived to %.4f m, rests at %.4f m (surface %.4f m), speed %.4f m/s; "
              "largest energy gain %.2e J (drop energy %.2e J)\n",
              lowest, z, level, body(run).linearVelocity().norm(), gain, drop);
  EXPECT_LT(lowest, level - 0.01);  // it dived in
  EXPECT_NEAR(z, level, 0.3 * 0.03);  // half submerged, give or take
  EXPECT_LT(body(run).linearVelocity().norm(), 0.05);
  EXPECT_LT(gain, 0.1 * drop);
}

TEST(FloatingBodies, RigidBodyFallsOntoTheFloorTipsFlatAndRests) {
  // No fluid: gravity and the container's inelastic contact alone. A box released 10 cm up,
  // tilted by 0.3 rad, lands on an edge, tips onto a face and stays.
  pbf::Obstacle box;
  box.shape = pbf::Obstacle::Shape::Box;
  box.half_extents = Eigen::Vector3f(0.05f, 0.04f, 0.02f);
  box.pose = Eigen::Translation3f(0.2f, 0.2f, 0.12f) * Eigen::AngleAxisf(0.3f, Eigen::Vector3f::UnitY());
  const double mass = 1.0;
  pbf::RigidBody body(box, mass, pbf::solidInertia(box, mass));
  const Eigen::AlignedBox3f container(Eigen::Vector3f::Zero(), Eigen::Vector3f(0.4f, 0.4f, 0.4f));
  const double e0 = body.kineticEnergy() + mass * 9.81 * 0.12;
  for (int k = 0; k < 1200; ++k) {  // 2 s at 1/600 s
    body.step(pbf::Wrench(), Eigen::Vector3d(0, 0, -9.81), 1.0 / 600.0);
    body.collide(container, Eigen::Isometry3f::Identity());
    const double e = body.kineticEnergy() + mass * 9.81 * body.shape().pose.translation().z();
    ASSERT_LT(e, e0 + 1e-3) << "energy from nowhere at step " << k;
  }
  const Eigen::Isometry3f& pose = body.shape().pose;
  const double tilt = std::acos(std::min(1.0f, std::abs(pose.linear()(2, 2))));
  std::printf("box on the floor: centre z %.4f m (half height 0.02), tilt %.4f rad, speed %.2e m/s\n",
              pose.translation().z(), tilt, body.linearVelocity().norm());
  EXPECT_NEAR(pose.translation().z(), 0.02, 1e-3);
  EXPECT_LT(tilt, 0.02);
  EXPECT_LT(body.linearVelocity().norm(), 1e-2);
  EXPECT_LT(body.angularVelocity().norm(), 0.1);
  EXPECT_THROW(pbf::RigidBody(box, -1.0, pbf::solidInertia(box, 1.0)), std::invalid_argument);
  EXPECT_THROW(pbf::RigidBody(box, 1.0, Eigen::Matrix3d::Zero()), std::invalid_argument);
}

// A body far lighter than the water (a helper probe's 1e-6 kg/m^3) took the node down: its
// pose overflowed to infinity and the solver refused it (std::invalid_argument). Scenes now
// refuse such bodies, and a body whose step would overflow stays where it was, at rest; its
// speed, and its rim's, keep to the fluid's cap.
TEST(FloatingBodies, ABodyTooLightOrTooLargeIsRefusedAndNoStepLeavesAPoseThatIsNotFinite) {
  pbf::Obstacle ball;
  ball.shape = pbf::Obstacle::Shape::Sphere;
  ball.radius = 0.05f;
  ball.pose = Eigen::Translation3f(0.2f, 0.2f, 0.1f) * Eigen::Quaternionf::Identity();
  pbf::Scene scene = tank(0.4f, 0.1f, ball);
  const double volume = pbf::solidVolume(ball);
  for (double density : {1e-6, 1.0, 19.0}) {
    scene.floating = {{0, density * volume, pbf::solidInertia(ball, density * volume)}};
    EXPECT_NE(scene.validate().find("below 2 % of the fluid's rest density"), std::string::npos) << density;
  }
  scene.floating = {{0, 20.0 * volume, pbf::solidInertia(ball, 20.0 * volume)}};
  EXPECT_EQ(scene.validate(), "");
  // Nor a body larger than the container (a probe's 1 m raft in a 0.6 x 0.4 m tank ended half
  // outside it): the tank here is 0.4 m wide.
  pbf::Scene raft = scene;
  raft.obstacles[0].shape = pbf::Obstacle::Shape::Box;
  raft.obstacles[0].half_extents = Eigen::Vector3f(0.25f, 0.1f, 0.02f);
  raft.floating = {{0, 500.0 * pbf::solidVolume(raft.obstacles[0]),
                    pbf::solidInertia(raft.obstacles[0], 500.0 * pbf::solidVolume(raft.obstacles[0]))}};
  EXPECT_NE(raft.validate().find("does not fit in the container"), std::string::npos) << raft.validate();

  pbf::RigidBody light(ball, 1e-12, pbf::solidInertia(ball, 1e-12));
  pbf::Wrench push;
  push.force = Eigen::Vector3d(1e300, 0.0, 0.0);
  push.torque = Eigen::Vector3d(0.0, 0.0, 1e300);
  EXPECT_FALSE(light.step(push, Eigen::Vector3d(0, 0, -9.81), 1e-3));
  EXPECT_TRUE(light.shape().pose.matrix().allFinite());
  EXPECT_NEAR(light.shape().pose.translation().x(), 0.2f, 1e-6f);
  EXPECT_EQ(light.linearVelocity().norm(), 0.0);

  pbf::RigidBody capped(ball, 1.0, pbf::solidInertia(ball, 1.0));
  push.force = Eigen::Vector3d(1e6, 0.0, 0.0);
  push.torque = Eigen::Vector3d(0.0, 0.0, 1e6);
  EXPECT_TRUE(capped.step(push, Eigen::Vector3d::Zero(), 1e-3, 5.0));
  EXPECT_NEAR(capped.linearVelocity().norm(), 5.0, 1e-9);
  EXPECT_NEAR(capped.angularVelocity().norm() * ball.boundingRadius(), 5.0, 1e-6);
}

}  // namespace
