// The solver against the equations and against physics: one iteration equals a scalar
// implementation of eq 2, 6, 7, 11, 12; a tank settles; momentum is conserved; results
// do not depend on the thread count.

#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <random>

#include "FreeSurfaceLend.h"
#include "SolverTestUtil.h"
#include "pbf_ros/core/Kernels.h"
#include "pbf_ros/core/Metrics.h"

namespace {

using Points = std::vector<Eigen::Vector3f>;

// A cluster 20 % denser than rest, free in space (no container, no gravity).
Points compressedCluster(float d, int n_side, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> jitter(-0.05f * d, 0.05f * d);
  Points pts;
  for (int x = 0; x < n_side; ++x)
    for (int y = 0; y < n_side; ++y)
      for (int z = 0; z < n_side; ++z)
        pts.emplace_back(0.93f * d * x + jitter(rng), 0.93f * d * y + jitter(rng), 0.93f * d * z + jitter(rng));
  return pts;
}

pbf::SolverParams freeSpaceParams() {
  pbf::SolverParams p;
  p.gravity.setZero();
  p.adaptive_time_step = false;
  p.time_step = 1e-3f;
  p.min_iterations = p.max_iterations = 1;
  p.gauss_seidel = false;  // the Jacobi iteration the transcription below computes
  p.xsph_viscosity = 0.0f;
  p.vorticity_epsilon = 0.0f;
  p.max_speed_factor = 0.0f;
  return p;
}

// Scalar transcription of the seed's equations (with the particle mass in eq 7 and 12,
// which the seed's unit-mass notation leaves out), in double precision. Three departures
// from the seed, all ours on purpose: the density is summed with the Spiky kernel whose
// gradient eq 7 uses (Kernels.h), the mass in the sums is the lattice-normalised m / S, and
// a pull (lambda > 0, the two-sided constraint's) is taken at half its step
// (PullRelaxation.h). With
// SolverParams::free_surface_lend, eq 2's sum is lent what the free surface misses, read from
// |grad_i C_i| (FreeSurfaceLend.h; in free space a particle has no images to leave out).
Points referenceDelta(const Points& x, const pbf::SolverParams& p) {
  const double h = p.supportRadius(), m = p.densityMass(), rho0 = p.rest_density;
  const pbf::Kernels k(static_cast<float>(h));
  auto poly6 = [&](double r2) { return r2 < h * h ? double(k.poly6_coef) * std::pow(h * h - r2, 3) : 0.0; };
  auto density_kernel = [&](double r2) { const double r = std::sqrt(r2); return r < h ? double(k.spiky_coef) * std::pow(h - r, 3) : 0.0; };
  auto spiky = [&](const Eigen::Vector3d& r) -> Eigen::Vector3d {
    const double len = r.norm();
    if (len >= h || len == 0.0) return Eigen::Vector3d::Zero();
    return double(k.spiky_grad_coef) * (h - len) * (h - len) / len * r;
  };
  const std::size_t n = x.size();
  const pbf::FreeSurfaceLend lend(p.particle_spacing, p.supportRadius());
  std::vector<double> lambda(n);
  for (std::size_t i = 0; i < n; ++i) {
    double rho = m * density_kernel(0.0);
    Eigen::Vector3d gi = Eigen::Vector3d::Zero();
    double sum = 0.0;
    for (std::size_t j = 0; j < n; ++j) {
      if (j == i) continue;
      const Eigen::Vector3d r = (x[i] - x[j]).cast<double>();
      rho += m * density_kernel(r.squaredNorm());          // eq 2
      const Eigen::Vector3d g = (m / rho0) * spiky(r);     // eq 7, k = j (sign irrelevant)
      gi += g;                                              // eq 7, k = i
      sum += g.squaredNorm();
    }
    if (p.free_surface_lend) rho += rho0 * lend.fraction(static_cast<float>(gi.norm()));
    double c = rho / rho0 - 1.0;                            // eq 1
    if (p.unilateral_constraint) c = std::max(c, 0.0);
    lambda[i] = -c / (sum + gi.squaredNorm() + p.cfmEpsilon());  // eq 6
    if (lambda[i] > 0.0) lambda[i] *= 0.5;                       // a pull, relaxed
  }
  const double dq = p.scorr_delta_q * h;
  Points delta(n);
  for (std::size_t i = 0; i < n; ++i) {
    Eigen::Vector3d dp = Eigen::Vector3d::Zero();
    for (std::size_t j = 0; j < n; ++j) {
      if (j == i) continue;
      const Eigen::Vector3d r = (x[i] - x[j]).cast<double>();
      if (r.squaredNorm() >= h * h) continue;
      // eq 11 (Macklin's parenthesisation), times h^2 to make k dimensionless and times
      // (dt / (1/60 s))^2 to make it a pressure (see PbfSolver.cpp)
      const double time_scale = std::min(1.0, std::pow(p.time_step * 60.0, 2.0));
      const double scorr = -p.scorr_k * h * h * time_scale *
                           std::pow(poly6(r.squaredNorm()) / poly6(dq * dq), p.scorr_n);
      dp += (lambda[i] + lambda[j] + scorr) * spiky(r);    // eq 12
    }
    delta[i] = ((m / rho0) * dp).cast<float>();
  }
  return delta;
}

TEST(SolverPhysics, OneIterationMatchesScalarTranscriptionOfTheEquations) {
  for (bool surface_lend : {true, false})
    for (bool unilateral : {true, false})
      for (float scorr_k : {0.0f, 0.1f}) {
        pbf::SolverParams p = freeSpaceParams();
        p.free_surface_lend = surface_lend;
        p.unilateral_constraint = unilateral;
        p.scorr_k = scorr_k;
        p.time_step = 1.0f / 90.0f;  // s_corr at 44 % of its reference strength
        const Points x = compressedCluster(p.particle_spacing, 6, 1);
        pbf::PbfSolver solver;
        solver.setParams(p);
        solver.setContainer(Eigen::AlignedBox3f());  // empty: no walls
        solver.setParticles(x);
        solver.step();
        const Points moved = pbf_test::positionsById(solver);
        const Points ref = referenceDelta(x, p);
        double max_ref = 0.0, max_diff = 0.0;
        for (std::size_t i = 0; i < x.size(); ++i) {
          max_ref = std::max<double>(max_ref, ref[i].norm());
          max_diff = std::max<double>(max_diff, (moved[i] - x[i] - ref[i]).norm());
        }
        ASSERT_GT(max_ref, 1e-4 * p.particle_spacing) << "the cluster must be compressed";
        EXPECT_LT(max_diff, 1e-3 * max_ref)
            << "surface lend " << surface_lend << " unilateral " << unilateral << " s_corr k " << scorr_k;
      }
}

TEST(SolverPhysics, PressureSolveConservesMomentumWithoutGravityAndWalls) {
  for (bool gauss_seidel : {false, true}) {
    SCOPED_TRACE(gauss_seidel ? "Gauss-Seidel" : "Jacobi");
    pbf::SolverParams p = freeSpaceParams();
    p.min_iterations = p.max_iterations = 4;
    p.unilateral_constraint = false;  // also pulls: both signs of lambda exercised
    // Jacobi: s_corr at 100x the paper's k saturates its bound; a pair uses the smaller bound
    // of its two particles, so even then its pushes are equal and opposite. Gauss-Seidel: each
    // projection moves i and its neighbours by gradients that sum to zero.
    p.gauss_seidel = gauss_seidel;
    p.scorr_k = gauss_seidel ? 0.0f : 10.0f;
    pbf::PbfSolver solver;
    solver.setParams(p);
    solver.setContainer(Eigen::AlignedBox3f());
    solver.setParticles(compressedCluster(p.particle_spacing, 12, 2));
    for (int s = 0; s < 20; ++s) solver.step();
    double speed_sum = 0.0;
    for (const auto& v : solver.velocities()) speed_sum += v.norm();
    const Eigen::Vector3d momentum = pbf::velocitySum(solver.velocities());
    ASSERT_GT(speed_sum, 1e-3) << "the cluster must expand";
    // Every pair term is antisymmetric, so the sum cancels up to float round-off: ~1e-7
    // relative per term, growing like sqrt(terms).
    EXPECT_LT(momentum.norm(), 1e-5 * speed_sum) << momentum.transpose();
  }
}

TEST(SolverPhysics, HydrostaticTankSettlesAtRestDensityAndVolumeLevel) {
  pbf::Scene scene = pbf_test::loadScene("hydrostatic_tank");
  scene.solver.adaptive_time_step = false;
  scene.solver.time_step = 1.0f / 120.0f;
  scene.solver.density_tolerance = 0.005f;
  scene.solver.min_iterations = 2;
  scene.solver.max_iterations = 50;
  scene.solver.xsph_viscosity = 4.4e-4f;  // c = 0.05 at this dt and h
  auto solver = pbf_test::makeSolver(scene);
  const float d = scene.solver.particle_spacing;
  const Eigen::Vector2f floor_size = scene.container.sizes().head<2>();
  // The volume the water's mass implies (m = rho0 d^3: the volume of the start lattice).
  const double implied_level = solver->size() * scene.solver.particleMass() / scene.solver.rest_density /
                               (floor_size.x() * floor_size.y());

  pbf::StepStats st;
  while (solver->time() < 2.0) st = solver->step();
  double sum_v2 = 0.0;
  for (const auto& v : solver->velocities()) sum_v2 += v.squaredNorm();
  const double rms_speed = std::sqrt(sum_v2 / solver->size());
  const double level = pbf::freeSurfaceHeight(solver->positions(), d, scene.container);
  // Free-fall speed over the column height: the natural velocity scale of the tank.
  const double v_scale = std::sqrt(2.0 * 9.81 * implied_level);
  RecordProperty("avg_density_error", std::to_string(st.avg_density_error));
  RecordProperty("level_error", std::to_string(level / implied_level - 1.0));
  std::printf("hydrostatic: avg err %.4f %%, max err %.3f %%, max speed %.3f m/s, rms %.4f m/s, "
              "level %.4f m vs %.4f m implied\n", st.avg_density_error * 100, st.max_density_error * 100,
              st.max_speed, rms_speed, level, implied_level);

  // The solve stops at 0.5 % average compression before its last correction: after it the
  // error must not exceed that tolerance by more than 20 %.
  EXPECT_LT(st.avg_density_error, 0.006);
  // No particle may be compressed by more than 5 % (10x the average budget).
  EXPECT_LT(st.max_density_error, 0.05);
  // At rest up to PBF's position-correction jitter: the bulk moves at under 2 % and no
  // particle at over 25 % of the free-fall speed (2.4 m/s here).
  EXPECT_LT(rms_speed, 0.02 * v_scale);
  EXPECT_LT(st.max_speed, 0.25 * v_scale);
  // With the start lattice and the walls calibrated nothing offsets the free surface's own
  // deficit any more: unilateral PBF lets the top layer sink until its truncated kernel sum
  // reaches rho0, about a third of a spacing (-2.1 % here; it was -1.0 % when the 1 % lattice
  // over-density and the walls' over-lending pushed the bulk up). A surface treatment is the
  // open item; the bound keeps the level from getting worse.
  EXPECT_NEAR(level / implied_level, 1.0, 0.03);
  EXPECT_EQ(pbf::countOutside(solver->positions(), scene.container, 0.0f), 0u);
}

void expectIdenticalForOneAndTwoThreadsAndAcrossRuns(const pbf::Scene& scene) {
  std::vector<Points> results;
  for (int threads : {1, 2, 2}) {
    omp_set_num_threads(threads);
    auto solver = pbf_test::makeSolver(scene);
    for (int s = 0; s < 60; ++s) solver->step();
    results.push_back(pbf_test::positionsById(*solver));
  }
  omp_set_num_threads(omp_get_num_procs());
  for (std::size_t i = 0; i < results[0].size(); ++i) {
    ASSERT_EQ(results[0][i], results[1][i]) << "1 vs 2 threads, particle " << i;
    ASSERT_EQ(results[1][i], results[2][i]) << "run 1 vs run 2, particle " << i;
  }
}

pbf::Scene determinismScene() {
  pbf::Scene scene = pbf_test::loadScene("dam_break");
  scene.solver.particle_spacing = 0.04f;
  scene.solver.density_tolerance = 0.01f;  // iteration count depends on reductions
  scene.solver.max_iterations = 10;
  scene.solver.vorticity_epsilon = 0.05f;
  scene.solver.neighbor_skin = 0.1f;
  return scene;
}

TEST(SolverPhysics, ResultsIdenticalForOneAndTwoThreadsAndAcrossRuns) {
  expectIdenticalForOneAndTwoThreadsAndAcrossRuns(determinismScene());
}

// max_iterations bounds a step's cost; a step that stops there before its tolerance says
// so (the node turns it into a /diagnostics warning), one that meets it or runs a fixed
// count does not.
TEST(SolverPhysics, StepThatStopsAtTheIterationCapSaysSo) {
  auto capReached = [](float tolerance, int max_iterations) {
    pbf::Scene scene = determinismScene();
    scene.solver.density_tolerance = tolerance;
    scene.solver.min_iterations = 2;
    scene.solver.max_iterations = max_iterations;
    auto solver = pbf_test::makeSolver(scene);
    int capped = 0;
    for (int s = 0; s < 5; ++s) {
      const pbf::StepStats st = solver->step();
      EXPECT_EQ(st.iteration_cap_reached, st.iterations == max_iterations && tolerance > 0.0f);
      EXPECT_EQ(st.iteration_cap_reached,
                tolerance > 0.0f &&
                    !st.skipped_stages.has(pbf::SkippedStages::kIterationsAfterTolerance));
      capped += st.iteration_cap_reached ? 1 : 0;
    }
    return capped;
  };
  EXPECT_EQ(capReached(1e-7f, 3), 5);  // unreachable in 3 corrections: every step capped
  EXPECT_EQ(capReached(0.05f, 30), 0);  // 5 %: met after the two forced corrections
  EXPECT_EQ(capReached(0.0f, 3), 0);    // a fixed count has no tolerance to miss
}

// The projected solve, the kept multipliers and the acceleration's positions (re-sorted with
// the particles when the lists are rebuilt within a solve) are no exception.
TEST(SolverPhysics, WarmStartedAndAcceleratedResultsIdenticalForOneAndTwoThreads) {
  pbf::Scene scene = determinismScene();
  scene.solver.density_tolerance = 0.001f;  // enough iterations for the acceleration to act
  scene.solver.max_iterations = 30;
  scene.solver.gauss_seidel = false;
  scene.solver.warm_start = true;
  scene.solver.chebyshev_rho = 0.9f;
  scene.solver.neighbor_skin = 0.01f;  // lists rebuilt (particles re-sorted) within solves
  expectIdenticalForOneAndTwoThreadsAndAcrossRuns(scene);
}

// The Gauss-Seidel sweeps (blocks of cells in 8 colours, each shared among the threads by
// its particles: BlockColours.h), lists rebuilt within solves.
TEST(SolverPhysics, GaussSeidelResultsIdenticalForOneAndTwoThreads) {
  pbf::Scene scene = determinismScene();
  scene.solver.density_tolerance = 0.001f;
  scene.solver.max_iterations = 30;
  scene.solver.min_iterations = 1;
  scene.solver.gauss_seidel = true;
  scene.solver.neighbor_skin = 0.01f;  // lists rebuilt (particles re-sorted) within solves
  expectIdenticalForOneAndTwoThreadsAndAcrossRuns(scene);
}

}  // namespace
