// pbf_step_benchmark: Google Benchmark of one solver step on the dam break, the figures of
// the README's performance table. 4 fixed iterations, fixed dt, 1 and 2 threads; and the
// cost of boundary handling (clamp only / wall density / with obstacles).
//   pbf_step_benchmark --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
// Each run first simulates 0.25 s (warm-up into a realistic, splashing state), then times
// steps; per-stage times are reported as counters (ms per step).

#include <benchmark/benchmark.h>
#include <omp.h>

#include <map>
#include <memory>

#include "pbf_ros/core/PbfSolver.h"
#include "pbf_ros/core/Scene.h"
#include "pbf_ros/core/SceneSetup.h"
#include "pbf_ros/core/SignedDistanceGrid.h"
#include "pbf_ros/core/TriangleMesh.h"

#ifndef PBF_SOURCE_DIR
#define PBF_SOURCE_DIR "."
#endif

namespace {

// Spacing for about 20k, 80k and 320k particles in the default dam break.
float spacingFor(int kilo_particles) {
  switch (kilo_particles) {
    case 20: return 0.02f;
    case 80: return 0.0126f;
    default: return 0.0079f;
  }
}

// Boundary variants for the cost of boundary handling: the seed's clamp only, wall
// density (the default), and wall density plus two obstacles in the flow.
// kFarRobot: wall density plus a robot of 30 links standing beside the tank, none within
// reach of the fluid (issue 12: solids far from the fluid should cost nothing).
enum Boundary { kClampOnly = 0, kWallDensity = 1, kWallDensityAndObstacles = 2, kFarRobot = 3 };

// 30 solids as a URDF's links would give them (boxes, cylinders, spheres and meshes through
// their signed distance grids), in a column beside the dam break's tank (x > 1.6 m).
std::vector<pbf::Obstacle> farRobotLinks(float spacing, float support_radius) {
  pbf::TriangleMesh mesh;  // a 6 x 6 x 10 cm box as a mesh: the link geometry of a URDF
  for (int c = 0; c < 8; ++c)
    mesh.vertices.emplace_back(c & 1 ? 0.03f : -0.03f, c & 2 ? 0.03f : -0.03f, c & 4 ? 0.05f : -0.05f);
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    mesh.triangles.emplace_back(q[0], q[1], q[2]);
    mesh.triangles.emplace_back(q[0], q[2], q[3]);
  }
  pbf::SignedDistanceGridOptions grid;  // as the robot loader builds them
  grid.cell = 0.5f * spacing;
  grid.band = support_radius + spacing;
  const auto sdf = pbf::SignedDistanceGrid::build(mesh, grid);
  std::vector<pbf::Obstacle> links;
  for (int k = 0; k < 30; ++k) {
    pbf::Obstacle o;
    switch (k % 4) {
      case 0: o.shape = pbf::Obstacle::Shape::Box; o.half_extents = Eigen::Vector3f(0.03f, 0.03f, 0.05f); break;
      case 1: o.shape = pbf::Obstacle::Shape::Cylinder; o.radius = 0.03f; o.half_length = 0.05f; break;
      case 2: o.shape = pbf::Obstacle::Shape::Sphere; o.radius = 0.04f; break;
      default: o.shape = pbf::Obstacle::Shape::Mesh; o.sdf = sdf; break;
    }
    o.pose.translation() = Eigen::Vector3f(1.8f + 0.1f * (k % 3), 0.25f, 0.05f + 0.1f * (k / 3));
    links.push_back(o);
  }
  return links;
}

// gauss_seidel: the same steps with 4 Gauss-Seidel sweeps instead of 4 Jacobi iterations
// (SolverParams::gauss_seidel): the cost of one sweep against one Jacobi iteration.
std::unique_ptr<pbf::PbfSolver> makeWarmSolver(int kilo_particles, int boundary = kWallDensity,
                                               bool gauss_seidel = false) {
  pbf::Scene scene = pbf::loadSceneFile(std::string(PBF_SOURCE_DIR) + "/config/scenes/dam_break.yaml");
  scene.solver.wall_density = boundary != kClampOnly;
  if (boundary == kWallDensityAndObstacles) {
    pbf::Obstacle pillar;
    pillar.shape = pbf::Obstacle::Shape::Capsule;
    pillar.radius = 0.05f;
    pillar.half_length = 0.3f;
    pillar.pose.translation() = Eigen::Vector3f(0.8f, 0.25f, 0.3f);
    pbf::Obstacle block;
    block.shape = pbf::Obstacle::Shape::Box;
    block.half_extents = Eigen::Vector3f(0.05f, 0.1f, 0.05f);
    block.pose.translation() = Eigen::Vector3f(1.2f, 0.25f, 0.05f);
    scene.obstacles = {pillar, block};
  }
  if (boundary == kFarRobot)
    scene.obstacles = farRobotLinks(spacingFor(kilo_particles), 2.0f * spacingFor(kilo_particles));
  scene.solver.particle_spacing = spacingFor(kilo_particles);
  scene.solver.adaptive_time_step = false;
  scene.solver.time_step = 1.0f / 400.0f;
  scene.solver.min_iterations = scene.solver.max_iterations = 4;
  scene.solver.density_tolerance = 0.0f;
  scene.solver.gauss_seidel = gauss_seidel;
  auto solver = std::make_unique<pbf::PbfSolver>();
  pbf::setUpSolver(scene, *solver);
  while (solver->time() < 0.25) solver->step();
  return solver;
}

void BM_DamBreakStep(benchmark::State& state) {
  const int kilo = static_cast<int>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  const int boundary = static_cast<int>(state.range(2));
  omp_set_num_threads(threads);
  const bool gauss_seidel = state.range(3) != 0;
  auto solver = makeWarmSolver(kilo, boundary, gauss_seidel);
  pbf::StageTimes sum;
  for (auto _ : state) {
    const pbf::StepStats st = solver->step();
    sum.neighbors_ms += st.times.neighbors_ms;
    sum.solve_ms += st.times.solve_ms;
    sum.viscosity_vorticity_ms += st.times.viscosity_vorticity_ms;
    sum.other_ms += st.times.other_ms;
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["particles"] = static_cast<double>(solver->size());
  state.counters["neighbors_ms"] = sum.neighbors_ms / n;
  state.counters["solve_ms"] = sum.solve_ms / n;
  state.counters["visc_vort_ms"] = sum.viscosity_vorticity_ms / n;
  state.counters["other_ms"] = sum.other_ms / n;
  state.counters["ns_per_particle"] = benchmark::Counter(
      static_cast<double>(solver->size()) * n, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  omp_set_num_threads(omp_get_num_procs());
}

// What every registration of BM_DamBreakStep shares: its argument names, and wall-clock
// milliseconds over at least a second per repetition.
void timedDamBreak(benchmark::internal::Benchmark* b) {
  b->ArgNames({"kparticles", "threads", "boundary", "gauss_seidel"})
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime()
      ->MinTime(1.0);
}

}  // namespace

// Scaling with particle count and threads (default boundaries).
BENCHMARK(BM_DamBreakStep)
    ->ArgsProduct({{20, 80, 320}, {1, 2}, {kWallDensity}, {0}})
    ->Apply(timedDamBreak);

// Cost of boundary handling: clamp only (0), wall density (1), plus obstacles (2).
BENCHMARK(BM_DamBreakStep)
    ->Name("BM_BoundaryCost")
    ->ArgsProduct({{20}, {2}, {kClampOnly, kWallDensity, kWallDensityAndObstacles}, {0}})
    ->Apply(timedDamBreak);

// 30 robot links beside the tank, far from the fluid (3) against none (1), one thread:
//   pbf_step_benchmark --benchmark_filter=BM_FarRobotLinks --benchmark_repetitions=5
BENCHMARK(BM_DamBreakStep)
    ->Name("BM_FarRobotLinks")
    ->ArgsProduct({{20}, {1}, {kWallDensity, kFarRobot}, {0}})
    ->Apply(timedDamBreak);

// One Gauss-Seidel sweep against one Jacobi iteration (4 of each per step), 20k particles:
//   pbf_step_benchmark --benchmark_filter=BM_GaussSeidelCost --benchmark_repetitions=5
BENCHMARK(BM_DamBreakStep)
    ->Name("BM_GaussSeidelCost")
    ->ArgsProduct({{20}, {1, 2}, {kWallDensity}, {0, 1}})
    ->Apply(timedDamBreak);

// The shipped solve's scaling: 4 Gauss-Seidel sweeps per step at every size, beside the first
// registration's 4 Jacobi iterations (the baseline's solve, which issue 10's ratios compare);
// scripts/step_benchmark_slope.py fits the slopes of both from --benchmark_out's JSON:
//   pbf_step_benchmark --benchmark_filter=BM_GaussSeidelScaling --benchmark_repetitions=3
BENCHMARK(BM_DamBreakStep)
    ->Name("BM_GaussSeidelScaling")
    ->ArgsProduct({{20, 80, 320}, {1, 2}, {kWallDensity}, {1}})
    ->Apply(timedDamBreak);

BENCHMARK_MAIN();
