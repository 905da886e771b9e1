// The warm start (SolverParams::warm_start): each solve begins from half the previous
// step's summed multiplier. It must save iterations where the pressure field persists, and
// never start from a pressure that belongs to other particles or another fluid.

#include <gtest/gtest.h>

#include <cstdio>

#include "SolverTestUtil.h"

namespace {

struct TankRun {
  double mean_iterations = 0.0;  // over the last 0.4 s of 1 s
  double kinetic_energy = 0.0;   // at the end [J]
};

// The shipped tank at d = 0.04 m, fixed dt 1/120 s, iterating to 0.1 % average error.
TankRun settledTank(bool warm_start) {
  pbf::Scene scene = pbf_test::loadScene("hydrostatic_tank");
  scene.solver.particle_spacing = 0.04f;
  scene.solver.adaptive_time_step = false;
  scene.solver.time_step = 1.0f / 120.0f;
  scene.solver.density_tolerance = 1e-3f;
  scene.solver.max_iterations = 300;
  scene.solver.warm_start = warm_start;
  auto solver = pbf_test::makeSolver(scene);
  TankRun run;
  long long iterations = 0, steps = 0;
  while (solver->time() < 1.0 - 1e-9) {
    const pbf::StepStats st = solver->step();
    EXPECT_FALSE(st.failed);
    if (solver->time() > 0.6) iterations += st.iterations, ++steps;
    run.kinetic_energy = st.kinetic_energy;
  }
  run.mean_iterations = double(iterations) / steps;
  return run;
}

}  // namespace

TEST(WarmStart, SettledTankNeedsFewerIterationsAndGainsNoEnergy) {
  const TankRun cold = settledTank(false), warm = settledTank(true);
  std::printf("settled tank, d 0.04 m, dt 1/120 s, 0.1 %%: %.2f iterations cold, %.2f warm "
              "(the warm start counted); kinetic energy %.4f J cold, %.4f J warm\n",
              cold.mean_iterations, warm.mean_iterations, cold.kinetic_energy, warm.kinetic_energy);
  EXPECT_LT(warm.mean_iterations, 0.85 * cold.mean_iterations);
  EXPECT_LT(warm.kinetic_energy, 2.0 * cold.kinetic_energy + 1e-3);
}

TEST(WarmStart, OnlyFromAPressureOfTheseParticles) {
  pbf::Scene scene = pbf_test::loadScene("hydrostatic_tank");
  scene.solver.particle_spacing = 0.04f;
  scene.solver.warm_start = true;
  auto solver = pbf_test::makeSolver(scene);
  EXPECT_FALSE(solver->step().warm_started) << "the first step has no pressure to start from";
  EXPECT_TRUE(solver->step().warm_started);
  solver->setParticles(solver->positions());  // a new fluid: its pressure is unknown
  EXPECT_FALSE(solver->step().warm_started);
  EXPECT_TRUE(solver->step().warm_started);
  pbf::SolverParams finer = solver->params();
  finer.particle_spacing = 0.03f;  // another mass and kernel: the kept multipliers mean nothing
  solver->setParams(finer);
  EXPECT_FALSE(solver->step().warm_started);
  finer.warm_start = false;
  solver->setParams(finer);
  EXPECT_FALSE(solver->step().warm_started);
}
