// The Gauss-Seidel solve (SolverParams::gauss_seidel, GaussSeidelSweep.cpp): it must reach a
// tolerance in fewer iterations than the Jacobi solve, end below the tolerance it reports,
// move the fluid as the Jacobi solve does, and refuse the options it does not combine with.
// (Thread-count independence: test_solver_physics; the walls' forces: test_solid_wrenches.)

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <limits>
#include <random>
#include <string>

#include "BlockColours.h"
#include "SolverTestUtil.h"
#include "pbf_ros/core/Metrics.h"
#include "pbf_ros/core/NeighborGrid.h"

namespace {

struct SolveRun {
  double mean_iterations = 0.0;  // per step, over the measured span
  double density_error = 0.0;    // average after the solve, over the measured span
  double worst_density_error = 0.0;  // the largest step average
  double kinetic_energy = 0.0;   // at the end [J]
  float front = 0.0f;            // largest x at the end [m]
};

SolveRun run(pbf::Scene scene, bool gauss_seidel, float tolerance, double seconds, double measure_from) {
  scene.solver.particle_spacing = 0.04f;
  scene.solver.adaptive_time_step = false;
  scene.solver.time_step = 1.0f / 120.0f;
  scene.solver.density_tolerance = tolerance;
  scene.solver.max_iterations = 300;
  scene.solver.min_iterations = 1;
  scene.solver.gauss_seidel = gauss_seidel;
  auto solver = pbf_test::makeSolver(scene);
  SolveRun r;
  long long iterations = 0, steps = 0;
  while (solver->time() < seconds - 1e-9) {
    const pbf::StepStats st = solver->step();
    EXPECT_FALSE(st.failed);
    EXPECT_FALSE(st.iteration_cap_reached);
    if (solver->time() > measure_from) {
      iterations += st.iterations, ++steps;
      r.density_error += st.avg_density_error;
      r.worst_density_error = std::max(r.worst_density_error, double(st.avg_density_error));
    }
    r.kinetic_energy = st.kinetic_energy;
  }
  r.mean_iterations = double(iterations) / std::max(1LL, steps);
  r.density_error /= std::max(1LL, steps);
  for (const auto& p : solver->positions()) r.front = std::max(r.front, p.x());
  return r;
}

}  // namespace

// A resting column's pressure: a Jacobi iteration carries a correction one neighbourhood
// deeper, a sweep as deep as its order allows.
TEST(GaussSeidel, SettledTankNeedsFewerIterationsAndEndsBelowItsTolerance) {
  const pbf::Scene tank = pbf_test::loadScene("hydrostatic_tank");
  const float tolerance = 1e-3f;
  const SolveRun gs = run(tank, true, tolerance, 1.0, 0.6);
  // At a matched error: the sweeps' stop test is conservative (below), so the Jacobi solve
  // is asked for the error the sweeps reached.
  const SolveRun jacobi = run(tank, false, static_cast<float>(gs.density_error), 1.0, 0.6);
  std::printf("settled tank, d 0.04 m, dt 1/120 s: Gauss-Seidel at 0.1 %% tolerance %.2f sweeps, "
              "density error %.4f %% (worst step %.4f %%), %.4f J; Jacobi to that error %.2f "
              "iterations, %.4f %%, %.4f J\n",
              gs.mean_iterations, 100 * gs.density_error, 100 * gs.worst_density_error,
              gs.kinetic_energy, jacobi.mean_iterations, 100 * jacobi.density_error,
              jacobi.kinetic_energy);
  EXPECT_LT(gs.mean_iterations, 0.5 * jacobi.mean_iterations);
  // The stop test measures the density after each sweep: every step ends below it.
  EXPECT_LE(gs.worst_density_error, tolerance);
  EXPECT_LT(gs.kinetic_energy, 2.0 * jacobi.kinetic_energy + 1e-3);
}

// The same flow: the dam break's front and kinetic energy at 0.5 s, both solves at a tight
// tolerance (where the two must converge to the same incompressible motion).
TEST(GaussSeidel, DamBreakMovesAsTheJacobiSolveDoes) {
  const pbf::Scene dam = pbf_test::loadScene("dam_break");
  const SolveRun gs = run(dam, true, 3e-4f, 0.5, 0.0);
  const SolveRun jacobi = run(dam, false, 3e-4f, 0.5, 0.0);
  std::printf("dam break, d 0.04 m, 0.5 s, tolerance 0.03 %%: Gauss-Seidel %.2f sweeps, front "
              "%.3f m, %.3f J; Jacobi %.2f iterations, front %.3f m, %.3f J\n",
              gs.mean_iterations, gs.front, gs.kinetic_energy, jacobi.mean_iterations, jacobi.front,
              jacobi.kinetic_energy);
  EXPECT_NEAR(gs.front, jacobi.front, 0.04f);  // one spacing
  EXPECT_NEAR(gs.kinetic_energy, jacobi.kinetic_energy, 0.05 * jacobi.kinetic_energy);
  EXPECT_LT(gs.mean_iterations, jacobi.mean_iterations);
}

TEST(GaussSeidel, RefusesWhatItDoesNotCombineWithAndKeepsThePreviousParameters) {
  pbf::PbfSolver solver;
  pbf::SolverParams good;
  good.gauss_seidel = true;
  solver.setParams(good);
  auto refused = [&](pbf::SolverParams p, const std::string& named) {
    try {
      solver.setParams(p);
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(named), std::string::npos) << e.what();
      EXPECT_TRUE(solver.params().gauss_seidel);
      EXPECT_EQ(solver.params().gauss_seidel_omega, good.gauss_seidel_omega);
      return true;
    }
    return false;
  };
  pbf::SolverParams p = good;
  p.warm_start = true;
  EXPECT_TRUE(refused(p, "warm_start"));
  p = good;
  p.chebyshev_rho = 0.9f;
  EXPECT_TRUE(refused(p, "chebyshev_rho"));
  p = good;
  p.scorr_k = 0.1f;
  EXPECT_TRUE(refused(p, "scorr_k"));
  for (float omega : {0.0f, 2.0f, -1.0f, std::numeric_limits<float>::quiet_NaN()}) {
    p = good;
    p.gauss_seidel_omega = omega;
    EXPECT_TRUE(refused(p, "gauss_seidel_omega")) << omega;
  }
}

// Each thread's share of a colour's blocks (BlockColours::share): the shares are consecutive
// runs that cover the colour once, and each holds its part of the particles to within one
// block, on a cloud as uneven as a dam break's (a dense slab and a thin spray).
TEST(GaussSeidel, ThreadsShareEachColoursParticlesEvenlyInConsecutiveRuns) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<Eigen::Vector3f> points;
  for (int i = 0; i < 20000; ++i) points.emplace_back(0.3f * u(rng), 0.2f * u(rng), 0.2f * u(rng));
  for (int i = 0; i < 2000; ++i) points.emplace_back(0.3f + 0.7f * u(rng), 0.2f * u(rng), 0.2f * u(rng));
  pbf::NeighborGrid grid;
  grid.build(points, 0.04f, Eigen::AlignedBox3f());
  pbf::BlockColours colours;
  colours.build(grid);
  std::size_t covered = 0;
  for (int colour = 0; colour < pbf::BlockColours::kColours; ++colour) {
    const pbf::BlockColours::Block* blocks = colours.first(colour);
    const std::size_t count = colours.count(colour);
    std::size_t total = 0, largest = 0;
    for (std::size_t q = 0; q < count; ++q) {
      total += blocks[q].end - blocks[q].begin;
      largest = std::max<std::size_t>(largest, blocks[q].end - blocks[q].begin);
    }
    covered += total;
    for (int threads : {1, 2, 3, 8}) {
      std::size_t next = 0;
      for (int t = 0; t < threads; ++t) {
        const auto [begin, end] = colours.share(colour, t, threads);
        EXPECT_EQ(begin, next) << "colour " << colour << ", thread " << t << " of " << threads;
        ASSERT_LE(begin, end);
        std::size_t held = 0;
        for (std::size_t q = begin; q < end; ++q) held += blocks[q].end - blocks[q].begin;
        EXPECT_NEAR(static_cast<double>(held), static_cast<double>(total) / threads, largest + 1.0)
            << "colour " << colour << ", thread " << t << " of " << threads;
        next = end;
      }
      EXPECT_EQ(next, count) << "colour " << colour << ", " << threads << " threads";
    }
  }
  EXPECT_EQ(covered, points.size());
}
