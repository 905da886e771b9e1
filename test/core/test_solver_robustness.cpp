// Hostile starts and bad input: no NaN, no escape, clear errors.

#include <gtest/gtest.h>

#include <cmath>

#include "SolverTestUtil.h"
#include "pbf_ros/core/Metrics.h"

namespace {

using Points = std::vector<Eigen::Vector3f>;

// Kinetic energy bound for hostile runs: every particle at the solver's speed cap
// (max_speed_factor * sqrt(2 |g| L)); anything above means energy came from nowhere.
double energyBound(const pbf::PbfSolver& s) {
  const double cap = s.params().max_speed_factor *
                     std::sqrt(2.0 * s.params().gravity.norm() * s.container().sizes().maxCoeff());
  return 0.5 * s.params().particleMass() * s.size() * cap * cap;
}

void expectSane(const pbf::PbfSolver& s, const pbf::StepStats& st, const char* what) {
  EXPECT_TRUE(pbf::allFinite(s.positions())) << what;
  EXPECT_TRUE(pbf::allFinite(s.velocities())) << what;
  EXPECT_EQ(pbf::countOutside(s.positions(), s.container(), 0.0f), 0u) << what;
  EXPECT_TRUE(std::isfinite(st.kinetic_energy)) << what;
  EXPECT_LE(st.kinetic_energy, energyBound(s) * 1.0001) << what;
  EXPECT_FALSE(st.failed) << what;
}

TEST(SolverRobustness, AllParticlesAtOnePointSpreadWithoutNaN) {
  pbf::Scene scene = pbf_test::loadScene("hydrostatic_tank");
  auto solver = pbf_test::makeSolver(scene);
  // The first steps cost N^2 (everyone neighbours everyone), so N stays moderate.
  const Points one_point(800, scene.container.center());
  solver->setParticles(one_point);
  pbf::StepStats st;
  for (int s = 0; s < 60; ++s) {
    st = solver->step();
    expectSane(*solver, st, "all at one point");
  }
  // Coincident pairs push apart along pseudo-random directions: the blob must spread.
  Eigen::AlignedBox3f bounds;
  for (const auto& p : solver->positions()) bounds.extend(p);
  EXPECT_GT(bounds.sizes().minCoeff(), 2.0f * scene.solver.particle_spacing);
}

TEST(SolverRobustness, LargeTimeStepWithOneIterationStaysFiniteAndInside) {
  pbf::Scene scene = pbf_test::loadScene("dam_break");
  scene.solver.particle_spacing = 0.04f;
  scene.solver.adaptive_time_step = false;
  scene.solver.time_step = 1.0f / 30.0f;
  scene.solver.min_iterations = scene.solver.max_iterations = 1;
  auto solver = pbf_test::makeSolver(scene);
  for (int s = 0; s < 90; ++s) expectSane(*solver, solver->step(), "dt = 1/30 s, 1 iteration");
}

TEST(SolverRobustness, OverflowingStepIsRejectedAndStateStaysFinite) {
  // Gravity near the float limit overflows velocities to Inf on the second step: the
  // attempt must be rejected and retried with a smaller dt; with no retries allowed the
  // step must fail and leave the state exactly as it was.
  pbf::SolverParams p;
  p.gravity = Eigen::Vector3f(0.0f, 0.0f, -3.0e38f);
  p.adaptive_time_step = false;
  p.time_step = 1.0f;
  p.max_speed_factor = 0.0f;
  pbf::PbfSolver solver;
  solver.setParams(p);
  solver.setContainer(Eigen::AlignedBox3f());
  solver.setParticles(Points{Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(0.01f, 0, 0)});
  solver.step();
  const Points before = solver.positions();
  const pbf::StepStats retried = solver.step();
  EXPECT_GE(retried.nan_retries, 1);
  EXPECT_LT(retried.dt, p.time_step);
  EXPECT_TRUE(pbf::allFinite(solver.positions()));
  EXPECT_TRUE(pbf::allFinite(solver.velocities()));

  p.max_nan_retries = 0;
  pbf::PbfSolver strict;
  strict.setParams(p);
  strict.setContainer(Eigen::AlignedBox3f());
  strict.setParticles(Points{Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(0.01f, 0, 0)});
  strict.step();
  const Points strict_before = strict.positions();
  const pbf::StepStats failed = strict.step();
  EXPECT_TRUE(failed.failed);
  EXPECT_EQ(failed.dt, 0.0);
  EXPECT_EQ(strict.positions(), strict_before);
  EXPECT_TRUE(pbf::allFinite(strict.velocities()));
}

TEST(SolverRobustness, NonFiniteParticlesAreRefusedWithTheirIndex) {
  pbf::PbfSolver solver;
  Points x{Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(NAN, 0, 0)};
  try {
    solver.setParticles(x);
    FAIL() << "NaN accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("particle 1"), std::string::npos) << e.what();
  }
  EXPECT_EQ(solver.size(), 0u);
}

TEST(SolverRobustness, BadParametersAreRefusedByNameAndOldOnesKept) {
  pbf::PbfSolver solver;
  pbf::SolverParams bad;
  bad.xsph_viscosity = NAN;
  try {
    solver.setParams(bad);
    FAIL() << "NaN accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("xsph_viscosity"), std::string::npos) << e.what();
  }
  EXPECT_EQ(solver.params().xsph_viscosity, pbf::SolverParams().xsph_viscosity);
  bad = pbf::SolverParams();
  bad.min_iterations = 5;
  bad.max_iterations = 2;
  EXPECT_THROW(solver.setParams(bad), std::invalid_argument);
  bad = pbf::SolverParams();
  bad.particle_spacing = -1.0f;
  EXPECT_THROW(solver.setParams(bad), std::invalid_argument);
}

TEST(SolverRobustness, ParticlesStartingOutsideTheBoxAreBroughtInside) {
  pbf::Scene scene = pbf_test::loadScene("hydrostatic_tank");
  auto solver = pbf_test::makeSolver(scene);
  Points x = solver->positions();
  for (std::size_t i = 0; i < x.size(); i += 7) x[i] += Eigen::Vector3f(3.0f, -2.0f, 5.0f);
  solver->setParticles(x);
  const pbf::StepStats st = solver->step();
  expectSane(*solver, st, "started outside");
}

}  // namespace
