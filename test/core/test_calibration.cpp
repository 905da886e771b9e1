// Calibration of the solver against its own start lattice and against dt and spacing:
// each test isolates one bias the calibration removed (LatticeBoundary.h, SolverParams.h).

#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <random>
#include <utility>

#include "SolverTestUtil.h"
#include "pbf_ros/core/Boundaries.h"
#include "pbf_ros/core/Kernels.h"
#include "pbf_ros/core/LatticeBoundary.h"
#include "pbf_ros/core/Metrics.h"
#include "pbf_ros/core/NeighborGrid.h"

namespace {

using Points = std::vector<Eigen::Vector3f>;

// Runs the solver to `to` seconds and returns the fluid's rms speed over [from, to], from the
// steps' kinetic energies weighted by their dt (NaN, and a failure, if a step fails).
double rmsSpeedBetween(pbf::PbfSolver& solver, const pbf::Scene& scene, double from, double to) {
  const double mass = solver.size() * double(scene.solver.particleMass());
  double energy = 0.0, seconds = 0.0;
  while (solver.time() < to) {
    const pbf::StepStats st = solver.step();
    if (st.failed) {
      ADD_FAILURE() << "step failed at " << solver.time() << " s";
      return NAN;
    }
    if (solver.time() > from) energy += st.kinetic_energy * st.dt, seconds += st.dt;
  }
  return std::sqrt(2.0 * energy / seconds / mass);
}

// A tank run for 1 s: its rms speed over the last quarter second and its level (the colour
// gauge's) as a fraction of the level its volume implies.
std::pair<double, double> restingTank(const pbf::Scene& scene) {
  auto solver = pbf_test::makeSolver(scene);
  const double rms = rmsSpeedBetween(*solver, scene, 0.75, 1.0);
  const double level = pbf::freeSurfaceHeight(solver->positions(), scene.solver.particle_spacing,
                                              scene.container) / pbf_test::impliedLevel(*solver, scene);
  return {rms, level};
}

// SPH density at p of the particles x (brute force, p's own particle included if in x).
double fluidDensityAt(const Eigen::Vector3f& p, const Points& x, const pbf::SolverParams& params) {
  const pbf::Kernels k(params.supportRadius());
  double rho = 0.0;
  for (const auto& q : x) rho += params.densityMass() * k.spiky((p - q).norm());
  return rho;
}

// SPH density of the particle at p from the lattice x (brute force) plus what the solids lend.
double densityAt(const Eigen::Vector3f& p, const Points& x, const pbf::SolverParams& params,
                 const pbf::SolidBoundaries& solids) {
  const double rho = fluidDensityAt(p, x, params);
  float fraction = 0.0f;
  Eigen::Vector3f gradient = Eigen::Vector3f::Zero();
  solids.density(p, fraction, gradient);
  return rho + params.rest_density * fraction;
}

// Cell-centred lattice filling [0, n d)^3, minus what lies closer than `gap` to an obstacle.
Points lattice(int n, float d, const std::vector<pbf::Obstacle>& obstacles = {}, float gap = -1.0f) {
  if (gap < 0.0f) gap = 0.5f * d;
  Points x;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const Eigen::Vector3f p((i + 0.5f) * d, (j + 0.5f) * d, (k + 0.5f) * d);
        bool inside = false;
        Eigen::Vector3f normal;
        for (const auto& o : obstacles) inside = inside || o.signedDistance(p, normal) < gap - 1e-6f;
        if (!inside) x.push_back(p);
      }
  return x;
}

// The container lends through mirror images inside the solver (ContainerMirror.h): its
// densities are read from the solver itself, after a step without gravity (nothing moves:
// a lattice at rest density has no active constraint). Also in a rotated, shifted container.
TEST(Calibration, RestingLatticeSumsToRestDensityInsideAtWallsEdgesAndCorners) {
  pbf::SolverParams params;
  params.gravity.setZero();
  params.xsph_viscosity = 0.0f;
  const float d = params.particle_spacing;
  const int n = 12;
  const Points x = lattice(n, d);
  const Eigen::AlignedBox3f box(Eigen::Vector3f::Zero(), Eigen::Vector3f::Constant(n * d));
  const float mid = (n / 2 + 0.5f) * d, lo = 0.5f * d, lo2 = 1.5f * d, hi = (n - 0.5f) * d;
  const std::vector<std::pair<const char*, Eigen::Vector3f>> where = {
      {"interior", {mid, mid, mid}}, {"floor", {mid, mid, lo}},   {"second layer", {mid, mid, lo2}},
      {"edge", {mid, lo, lo}},       {"corner", {lo, lo, lo}},    {"far corner", {hi, hi, hi}},
      {"edge, second layer", {mid, lo2, lo}}};
  Eigen::Isometry3f turned = Eigen::Isometry3f::Identity();
  turned.translate(Eigen::Vector3f(0.3f, -0.2f, 0.1f));
  turned.rotate(Eigen::AngleAxisf(0.7f, Eigen::Vector3f(1.0f, 2.0f, 3.0f).normalized()));
  for (const Eigen::Isometry3f& pose : {Eigen::Isometry3f(Eigen::Isometry3f::Identity()), turned}) {
    pbf::PbfSolver solver;
    solver.setParams(params);
    solver.setContainer(box);
    solver.setContainerPose(pose);
    Points placed;
    for (const auto& p : x) placed.push_back(pose * p);
    solver.setParticles(placed);
    solver.stepWith(1e-3f);
    for (const auto& [name, p] : where) {
      const Eigen::Vector3f at = pose * p;
      std::size_t best = 0;
      for (std::size_t i = 0; i < solver.size(); ++i)
        if ((solver.positions()[i] - at).squaredNorm() < (solver.positions()[best] - at).squaredNorm()) best = i;
      ASSERT_LT((solver.positions()[best] - at).norm(), 1e-4f * d) << name;
      const double rho = solver.densities()[best] / params.rest_density;
      std::printf("%-20s %s rho/rho0 = %.5f\n", name, pose.isApprox(turned) ? "turned" : "      ", rho);
      EXPECT_NEAR(rho, 1.0, 0.005) << name;  // the bound; the construction gives ~1e-5
      EXPECT_NEAR(rho, 1.0, 1e-4) << name;
    }
  }
}

TEST(Calibration, BoxObstacleAndThinPlateLendExactlyTheMissingDensity) {
  pbf::SolverParams params;
  const float d = params.particle_spacing;
  const int n = 16;
  const pbf::LatticeBoundary table(d, params.supportRadius());
  for (float half_thickness : {3.0f * d, 0.5f * d}) {  // a block, and a plate one layer thick
    pbf::Obstacle block;
    block.shape = pbf::Obstacle::Shape::Box;
    block.half_extents = Eigen::Vector3f(3.0f * d, 3.0f * d, half_thickness);
    // Faces halfway between lattice planes, as a scene's lattice leaves them.
    const float zc = half_thickness > d ? 8.0f * d : 8.5f * d;
    block.pose.translation() = Eigen::Vector3f(8.0f * d, 8.0f * d, zc);
    const std::vector<pbf::Obstacle> obstacles{block};
    const Points x = lattice(n, d, obstacles);
    // No container: only the obstacle lends density; probe away from the lattice's edges.
    const pbf::SolidBoundaries solids(Eigen::AlignedBox3f(), Eigen::Isometry3f::Identity(), obstacles,
                                      table, 0.5f * d);
    const float c = 8.0f * d, top = zc + half_thickness + 0.5f * d, side = c + 3.5f * d;
    const float level = half_thickness > d ? c + 0.5f * d : zc;  // a lattice plane beside it
    const std::vector<std::pair<const char*, Eigen::Vector3f>> where = {
        {"on the face", {c + 0.5f * d, c + 0.5f * d, top}},
        {"beside the face", {side, c + 0.5f * d, level}},
        {"over the edge", {side, c + 0.5f * d, top}},
        {"over the corner", {side, side, top}}};
    for (const auto& [name, p] : where) {
      const double rho = densityAt(p, x, params, solids) / params.rest_density;
      std::printf("half thickness %.3f, %-16s rho/rho0 = %.5f\n", half_thickness, name, rho);
      EXPECT_NEAR(rho, 1.0, 0.005) << name << ", half thickness " << half_thickness;
    }
  }
}

// A sphere of radius 2h in a resting lattice (fluid up to its surface, not aligned with
// it): the layer around it must not be over-dense, as the flat-wall fraction alone would
// make it (it lends a half-space's density to a convex surface).
TEST(Calibration, CurvedObstacleDoesNotOverLend) {
  pbf::SolverParams params;
  const float d = params.particle_spacing, h = params.supportRadius();
  const int n = 20;
  pbf::Obstacle ball;
  ball.shape = pbf::Obstacle::Shape::Sphere;
  ball.radius = 2.0f * h;
  ball.pose.translation() = Eigen::Vector3f::Constant(10.0f * d + 0.013f);  // off the lattice
  const std::vector<pbf::Obstacle> obstacles{ball};
  const Points x = lattice(n, d, obstacles, 0.0f);
  const pbf::LatticeBoundary table(d, h);
  const pbf::SolidBoundaries solids(Eigen::AlignedBox3f(), Eigen::Isometry3f::Identity(), obstacles, table,
                                    0.5f * d);
  double sum = 0.0;
  int count = 0;
  for (const auto& p : x) {
    Eigen::Vector3f normal;
    if (ball.signedDistance(p, normal) >= d) continue;  // the first layer
    sum += densityAt(p, x, params, solids) / params.rest_density;
    ++count;
  }
  ASSERT_GT(count, 50);
  const double mean = sum / count;
  std::printf("sphere of radius 2h: first layer (%d particles) mean rho/rho0 = %.4f\n", count, mean);
  EXPECT_LT(mean, 1.005);
  EXPECT_GT(mean, 0.98);
}

// A fresh scene starts at rest density: its first step moves by gravity alone (issue 9: at
// most 3 g dt at every dt from 1/1000 to 1/60 s), on the shipped scene at its own spacing
// and at the finer 0.0125 m. What the first step does depends on g dt^2 / d, how far gravity
// moves the column into the floor in one step, so the spacing matters (until session 36
// this test ran d = 0.04 m, where even 1/60 s needs one sweep).
//
// Until session 37 the sweeps failed it from about 1/75 s on (8.8 g dt at 1/60 s after 28
// sweeps; 10.5 at d = 0.0125 m): the free surface's lend was first measured at the
// predicted positions, where the floor's compressed layers looked like a free surface, and
// the sweeps that removed what it lent them drifted the floor's layers sideways. Lent where
// the fluid starts (NewParticleLends.cpp), one sweep suffices at every dt here.
TEST(Calibration, DamBreakFirstStepMovesByGravityAlone) {
  struct Case {
    float dt;
    bool sweeps;
    float spacing;
  };
  for (const Case& c : {Case{1.0f / 1000.0f, true, 0.02f}, Case{1.0f / 240.0f, true, 0.02f},
                        Case{1.0f / 120.0f, true, 0.02f}, Case{1.0f / 90.0f, true, 0.02f},
                        Case{1.0f / 60.0f, true, 0.02f}, Case{1.0f / 80.0f, true, 0.0125f},
                        Case{1.0f / 60.0f, true, 0.0125f}, Case{1.0f / 1000.0f, false, 0.02f},
                        Case{1.0f / 60.0f, false, 0.02f}}) {
    pbf::Scene scene = pbf_test::loadScene("dam_break");
    ASSERT_FLOAT_EQ(scene.solver.particle_spacing, 0.02f);  // the shipped spacing
    scene.solver.particle_spacing = c.spacing;
    scene.solver.gauss_seidel = c.sweeps;
    auto solver = pbf_test::makeSolver(scene);
    const pbf::StepStats st = solver->stepWith(c.dt);
    std::printf("%s, d %.4f m, dt 1/%.0f s: first-step max speed %.4f m/s = %.2f g dt (%d iterations)\n",
                c.sweeps ? "sweeps" : "Jacobi", c.spacing, 1.0 / c.dt, st.max_speed,
                st.max_speed / (9.81 * c.dt), st.iterations);
    EXPECT_LE(st.max_speed, 3.0 * 9.81 * c.dt)
        << (c.sweeps ? "sweeps" : "Jacobi") << ", d " << c.spacing << ", dt " << c.dt;
  }
}

// A tank at rest comes to rest. With the seed's kernels (Poly6 density, Spiky gradient) the
// correction is not along the gradient of the density it corrects, does work, and keeps the
// water moving for ever: rms speed ~0.1 m/s at the shipped defaults and ~0.35 m/s at a fixed
// dt of 1/480 s (more steps, more work). One kernel for both (Kernels.h): 0.035 m/s at the
// shipped defaults; at 1/480 s still 0.07 m/s (doc/calibration.md: not yet at rest).
TEST(Calibration, RestingTankComesToRest) {
  pbf::Scene scene = pbf_test::loadScene("hydrostatic_tank");
  auto solver = pbf_test::makeSolver(scene);
  const double rms = rmsSpeedBetween(*solver, scene, 1.5, 2.0);
  std::printf("resting tank, shipped defaults: rms speed over 1.5-2 s %.4f m/s\n", rms);
  EXPECT_LT(rms, 0.05);
}

// A wider support: more corrections overlap (latticeJacobiAmplification: the Jacobi solve's
// worst mode overshoots by 2.8 at h = 2d and 6.7 at 3d). Unrelaxed, the Jacobi solve blew a
// resting tank up at h = 3d (level 0.64 of the implied, rms speed 1.2 m/s at 1 s) and the
// sweeps kept it at 0.10 m/s. Relaxed by SolverParams::overlapRelaxation (the Jacobi
// multipliers, the sweeps' omega), the tank rests with either solve.
TEST(Calibration, WiderSupportIsRelaxedAndRestsWithEitherSolve) {
  // The amplification, against a Python transcription of the same Fourier sum (2.815 at
  // h = 2d on the same 17^3 points; 2.814 on 24^3 points of the whole zone).
  EXPECT_NEAR(pbf::latticeJacobiAmplification(2.0), 2.815, 0.005);
  EXPECT_GT(pbf::latticeJacobiAmplification(3.0), 2.0 * pbf::latticeJacobiAmplification(2.0));
  for (bool sweeps : {false, true}) {
    pbf::Scene scene = pbf_test::loadScene("hydrostatic_tank");
    EXPECT_EQ(scene.solver.overlapRelaxation(), 1.0f);  // the validated support: unchanged
    scene.solver.support_radius_factor = 3.0f;
    scene.solver.gauss_seidel = sweeps;
    EXPECT_NEAR(scene.solver.overlapRelaxation(), 0.42, 0.005);
    const auto [rms, level] = restingTank(scene);
    std::printf("h = 3d, %s: rms speed over 0.75-1 s %.4f m/s, level %.4f of the implied\n",
                sweeps ? "sweeps" : "Jacobi", rms, level);
    EXPECT_LT(rms, 0.05) << (sweeps ? "sweeps" : "Jacobi");
    EXPECT_NEAR(level, 1.0, 0.01) << (sweeps ? "sweeps" : "Jacobi");
  }
}

// The seed's two-sided constraint pulls expanded particles together as it pushes compressed
// ones apart. At a full Newton step the pulls fed energy in (PullRelaxation.h): with the
// Jacobi solve a tank at rest reached the speed cap (13.7 m/s) within 0.1 s, and with the
// over-relaxed sweeps the dam break did by 0.5 s (kinetic energy 1000 J, against the 600 J
// of potential energy it starts with). Pulls at half a step: the tank rests with either
// solve, and the dam break's speeds stay below the cap.
TEST(Calibration, TwoSidedConstraintRelaxesItsPullsAndStaysCalm) {
  for (bool sweeps : {false, true}) {
    SCOPED_TRACE(sweeps ? "sweeps" : "Jacobi");
    pbf::Scene scene = pbf_test::loadScene("hydrostatic_tank");
    scene.solver.unilateral_constraint = false;
    scene.solver.gauss_seidel = sweeps;
    const auto [rms, level] = restingTank(scene);
    std::printf("two-sided tank, %s: rms speed over 0.75-1 s %.4f m/s, level %.4f of the implied\n",
                sweeps ? "sweeps" : "Jacobi", rms, level);
    // Full pulls: 8.2 m/s with Jacobi. The two-sided jitters a little more than the
    // one-sided (pbf_run hydrostatic_tank --seconds 2 --set gauss_seidel=false: 0.056
    // against 0.039 m/s at the end), as its surface particles pull.
    EXPECT_LT(rms, 0.1);
    EXPECT_NEAR(level, 1.0, 0.01);
  }
  // The dam break's first 0.6 s, against the shipped one-sided constraint's.
  double fastest[2] = {0.0, 0.0};
  for (bool two_sided : {false, true}) {
    pbf::Scene scene = pbf_test::loadScene("dam_break");
    scene.solver.unilateral_constraint = !two_sided;
    auto solver = pbf_test::makeSolver(scene);
    int capped = 0;
    while (solver->time() < 0.6) {
      const pbf::StepStats st = solver->step();
      ASSERT_FALSE(st.failed) << "at " << solver->time() << " s";
      capped += st.speed_limited ? 1 : 0;
      fastest[two_sided] = std::max(fastest[two_sided], st.max_speed);
    }
    std::printf("dam break, sweeps, %s constraint: %d steps at the speed cap, largest speed %.2f m/s\n",
                two_sided ? "two-sided" : "one-sided", capped, fastest[two_sided]);
    EXPECT_EQ(capped, 0) << (two_sided ? "two-sided" : "one-sided");
  }
  EXPECT_LT(fastest[1], 1.2 * fastest[0]);
}

// The walls carry their share of the pressure gradient (mirror images, ContainerMirror.h):
// a tank started from the lattice and solved tightly, the columns along the walls and edges
// move no more than the middle ones. With ghost fluid fixed to the walls the edge columns,
// missing the wall side's push, slid down at 0.12 m/s within 0.1 s while the middle rose.
// The lattice itself then rearranges, as any particle fluid at rest does: the Jacobi solve
// keeps it still (< 0.05 m/s) for the first 0.2 s; under the Gauss-Seidel sweeps, whose
// residual is less even (max density error 0.22 % against 0.11 % at the same 0.03 %
// average), the rearrangement starts at ~0.1 s, in the middle, and reaches 0.13 m/s by 0.2 s.
TEST(Calibration, ColumnsAlongTheWallsAreHeldLikeTheMiddle) {
  for (bool gauss_seidel : {false, true}) {
    SCOPED_TRACE(gauss_seidel ? "Gauss-Seidel" : "Jacobi");
    pbf::Scene scene = pbf_test::loadScene("hydrostatic_tank");
    scene.solver.gauss_seidel = gauss_seidel;
    scene.solver.density_tolerance = 0.0003f;
    scene.solver.max_iterations = 200;
    auto solver = pbf_test::makeSolver(scene);
    const float d = scene.solver.particle_spacing;
    const Eigen::AlignedBox3f box = scene.container;
    auto alongAWall = [&](const Eigen::Vector3f& x) {
      for (int a = 0; a < 2; ++a)
        if (x[a] - box.min()[a] < 2 * d || box.max()[a] - x[a] < 2 * d) return true;
      return false;
    };
    double max_speed = 0.0, wall_v2 = 0.0, middle_v2 = 0.0;
    long long wall_n = 0, middle_n = 0;
    while (solver->time() < 0.2) {
      const pbf::StepStats st = solver->step();
      ASSERT_FALSE(st.failed);
      max_speed = std::max(max_speed, st.max_speed);
      const auto x = solver->positions();
      const auto v = solver->velocities();
      for (std::size_t i = 0; i < x.size(); ++i) {
        const bool wall = alongAWall(x[i]);
        (wall ? wall_v2 : middle_v2) += v[i].squaredNorm();
        ++(wall ? wall_n : middle_n);
      }
    }
    const double wall_rms = std::sqrt(wall_v2 / wall_n), middle_rms = std::sqrt(middle_v2 / middle_n);
    std::printf("lattice tank, tolerance 0.03 %%, %s: first 0.2 s max speed %.4f m/s, rms along the "
                "walls %.4f, in the middle %.4f m/s\n",
                gauss_seidel ? "Gauss-Seidel" : "Jacobi", max_speed, wall_rms, middle_rms);
    EXPECT_LT(wall_rms, 1.25 * middle_rms);
    if (!gauss_seidel) {
      EXPECT_LT(max_speed, 0.05);
    }
  }
}

// Wall friction is a physical law: the same sliding layer at two time steps slows the same.
TEST(Calibration, WallFrictionIsTheSameAtEveryTimeStep) {
  auto slide = [](float dt) {
    pbf::Scene scene = pbf_test::loadScene("hydrostatic_tank");
    scene.solver.particle_spacing = 0.025f;
    scene.solver.wall_friction = 0.5f;
    scene.solver.adaptive_time_step = false;
    scene.solver.time_step = dt;
    scene.fluid[0].max.z() = 0.05f;
    scene.fluid[0].velocity.x() = 0.5f;
    scene.fluid[0].max.x() = 0.2f;
    auto solver = pbf_test::makeSolver(scene);
    while (solver->time() < 0.2 - 1e-9) solver->step();
    double vx = 0.0;
    for (const auto& v : solver->velocities()) vx += v.x();
    return vx / solver->size();
  };
  const double coarse = slide(1.0f / 120.0f), fine = slide(1.0f / 480.0f);
  std::printf("mean vx after 0.2 s with c_f 0.5: dt 1/120 %.4f m/s, dt 1/480 %.4f m/s\n", coarse, fine);
  EXPECT_LT(fine, 0.45);  // it does slow the layer (free slip keeps 0.50 at both dt)
  // The law itself is integrated exactly per particle (u' = u / (1 + c_f |u| dt / d)); what
  // is left is the first-order splitting against the pressure solve and XSPH, which share
  // the bottom layer's loss with the layers above once per step: 5.2 % between 1/120 and
  // 1/480 s with the Spiky density kernel (1.8 % with Poly6).
  EXPECT_NEAR(coarse, fine, 0.06 * fine);
}

// A rejected step leaves every array as it was, in the order of the restored particles.
TEST(Calibration, RejectedStepRestoresDensitiesAndNeighbourCounts) {
  pbf::SolverParams p;
  p.gravity.setZero();
  p.max_nan_retries = 0;
  p.max_speed_factor = 0.0f;
  pbf::PbfSolver solver;
  solver.setParams(p);
  solver.setContainer(Eigen::AlignedBox3f());
  Points x;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j)
      for (int k = 0; k < 6; ++k) x.emplace_back(0.8f * p.particle_spacing * Eigen::Vector3f(i, j, k));
  solver.setParticles(x);
  solver.stepWith(1e-3f);
  const auto density = solver.densities();
  const auto counts = solver.neighborCounts();
  const auto ids = solver.ids();
  // The corrections divided by a denormal dt overflow the velocities: rejected at the end
  // of the attempt, after the lists, densities and counts were recomputed.
  const pbf::StepStats st = solver.stepWith(1e-44f);
  ASSERT_TRUE(st.failed);
  EXPECT_EQ(solver.ids(), ids);
  EXPECT_EQ(solver.densities(), density);
  EXPECT_EQ(solver.neighborCounts(), counts);
}

// Reused lists (skin) must still hold every pair within h after the solver's corrections:
// the final densities, computed from the lists, equal a brute-force sum (plus what the free
// surface lends, which does not depend on the lists' length).
TEST(Calibration, ReusedNeighbourListsNeverMissAPairWithinH) {
  pbf::SolverParams p;
  p.gravity.setZero();
  p.neighbor_skin = 0.5f;
  p.min_iterations = p.max_iterations = 6;
  p.density_tolerance = 0.0f;
  p.xsph_viscosity = 0.0f;
  p.max_speed_factor = 0.0f;
  pbf::PbfSolver solver;
  solver.setParams(p);
  solver.setContainer(Eigen::AlignedBox3f());
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  Points x, v;
  for (int i = 0; i < 700; ++i) {
    x.emplace_back(0.15f * Eigen::Vector3f(u(rng), u(rng), u(rng)));  // a loose random blob
    v.emplace_back(0.1f * Eigen::Vector3f(u(rng), u(rng), u(rng)));
  }
  solver.setParticles(x, v);
  int reused = 0;
  for (int s = 0; s < 20; ++s) {
    const pbf::StepStats st = solver.stepWith(2e-3f);
    reused += st.neighbor_lists_reused ? 1 : 0;
    const Points& pos = solver.positions();
    for (std::size_t i = 0; i < pos.size(); ++i) {
      const double rho = fluidDensityAt(pos[i], pos, p) + solver.surfaceLend(i);
      ASSERT_NEAR(solver.densities()[i], rho, 1e-4 * rho) << "step " << s << ", particle " << i;
    }
  }
  EXPECT_GT(reused, 5) << "the test must exercise reuse";
}

// A solve that ends on its tolerance measured the density at the final positions in its last
// lambda pass, and the step keeps those (no density pass): they must still be the densities
// and neighbour counts of the positions the step ends with, also when the lists were reused.
TEST(Calibration, DensitiesKeptFromTheSolveAreTheFinalPositionsDensities) {
  pbf::SolverParams p;
  p.gravity.setZero();
  p.neighbor_skin = 0.5f;
  p.min_iterations = 1;
  p.density_tolerance = 0.01f;
  p.max_speed_factor = 0.0f;
  pbf::PbfSolver solver;
  solver.setParams(p);
  solver.setContainer(Eigen::AlignedBox3f());
  Points x;  // a compressed block: the solve has work to do, and ends on its tolerance
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j)
      for (int k = 0; k < 8; ++k) x.emplace_back(0.9f * p.particle_spacing * Eigen::Vector3f(i, j, k));
  solver.setParticles(x);
  const pbf::Kernels k(p.supportRadius());
  int kept = 0;
  for (int s = 0; s < 15; ++s) {
    const pbf::StepStats st = solver.stepWith(2e-3f);
    kept += st.skipped_stages.has(pbf::SkippedStages::kDensityPass) ? 1 : 0;
    const Points& pos = solver.positions();
    for (std::size_t i = 0; i < pos.size(); ++i) {
      const double rho = fluidDensityAt(pos[i], pos, p) + solver.surfaceLend(i);
      int within = 0;
      for (std::size_t j = 0; j < pos.size(); ++j) within += j != i && (pos[i] - pos[j]).norm() < k.h ? 1 : 0;
      ASSERT_NEAR(solver.densities()[i], rho, 1e-4 * rho) << "step " << s << ", particle " << i;
      ASSERT_EQ(solver.neighborCounts()[i], within) << "step " << s << ", particle " << i;
    }
  }
  EXPECT_GT(kept, 5) << "the test must exercise the kept densities";
}

// Wall friction moves the particles it drags after the solve: then the step measures the
// density again instead of keeping the solve's.
TEST(Calibration, FrictionAfterTheSolveGetsItsOwnDensityPass) {
  pbf::SolverParams p;
  p.min_iterations = 1;
  p.density_tolerance = 0.01f;
  p.wall_friction = 1.0f;
  pbf::PbfSolver solver;
  solver.setParams(p);
  solver.setContainer(Eigen::AlignedBox3f(Eigen::Vector3f::Zero(), Eigen::Vector3f(0.4f, 0.4f, 0.4f)));
  Points x, v;  // one layer sliding along the floor
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j) {
      x.emplace_back(p.particle_spacing * Eigen::Vector3f(i + 0.5f, j + 0.5f, 0.5f));
      v.emplace_back(0.5f, 0.0f, 0.0f);
    }
  solver.setParticles(x, v);
  for (int s = 0; s < 5; ++s) {
    const pbf::StepStats st = solver.stepWith(2e-3f);
    ASSERT_FALSE(st.failed);
    EXPECT_FALSE(st.skipped_stages.has(pbf::SkippedStages::kDensityPass)) << "step " << s;
  }
  EXPECT_LT(solver.velocities()[0].x(), 0.5f);  // friction acted
}

// The grid covers the fluid, not the container: a small ball of fluid in a 20 m container
// needs no more cells than in a 0.4 m one.
TEST(Calibration, NeighbourGridFollowsTheFluidNotTheContainer) {
  auto cells = [](float container_size) {
    pbf::SolverParams p;
    pbf::PbfSolver solver;
    solver.setParams(p);
    solver.setContainer(Eigen::AlignedBox3f(Eigen::Vector3f::Zero(), Eigen::Vector3f::Constant(container_size)));
    Points x;
    const float d = p.particle_spacing;
    for (float a = -0.1f; a <= 0.1f; a += d)
      for (float b = -0.1f; b <= 0.1f; b += d)
        for (float c = -0.1f; c <= 0.1f; c += d)
          if (a * a + b * b + c * c <= 0.01f) x.emplace_back(Eigen::Vector3f(0.2f + a, 0.2f + b, 0.2f + c));
    solver.setParticles(x);
    return solver.step().grid_cells;
  };
  const std::size_t small = cells(0.4f), large = cells(20.0f);
  std::printf("grid cells for a 0.2 m ball: 0.4 m container %zu, 20 m container %zu\n", small, large);
  EXPECT_LE(large, small + small / 2);
}

}  // namespace
