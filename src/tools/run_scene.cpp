// pbf_run: runs a scene headless on the ROS-free core and prints progress and statistics.
//   pbf_run [scene name or path] [--seconds S] [--spacing D] [--scenes-dir DIR]
//           [--set solver_key=value]... [--track-wrenches]
// Floating (dynamic) obstacles move with the fluid. --track-wrenches measures the fluid's
// force on every solid each step (its cost shows in ms/step) and prints the last step's.

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>

#include "ToolArguments.h"
#include "pbf_ros/core/FloatingBodies.h"
#include "pbf_ros/core/FluidSources.h"
#include "pbf_ros/core/Metrics.h"
#include "pbf_ros/core/NeighborGrid.h"
#include "pbf_ros/core/PbfSolver.h"
#include "pbf_ros/core/Scene.h"
#include "pbf_ros/core/SceneSetup.h"

#ifndef PBF_SOURCE_DIR
#define PBF_SOURCE_DIR "."
#endif

int main(int argc, char** argv) {
  std::string scene_name = "dam_break";
  std::string scenes_dir = std::string(PBF_SOURCE_DIR) + "/config/scenes";
  double seconds = 2.0;
  float spacing = 0.0f;  // 0: the scene's
  std::size_t max_particles = 1000000;  // as the node's ~max_particles
  std::string overrides;  // YAML map of solver parameters from --set key=value
  bool track_wrenches = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::cerr << "pbf_run: " << a << " needs a value\n";
        std::exit(2);
      }
      return argv[++i];
    };
    try {
      if (a == "--seconds") {
        seconds = pbf_tools::finitePositive(a, value());
        continue;
      }
      if (a == "--spacing") {
        spacing = static_cast<float>(pbf_tools::finitePositive(a, value()));
        continue;
      }
      if (a == "--max-particles") {
        max_particles = static_cast<std::size_t>(pbf_tools::integerIn(a, value(), 1, 1000000000));
        continue;
      }
    } catch (const std::invalid_argument& e) {
      std::cerr << "pbf_run: " << e.what() << "\n";
      return 2;
    }
    if (a == "--scenes-dir") scenes_dir = value();
    else if (a == "--track-wrenches") track_wrenches = true;
    else if (a == "--set") {
      const std::string kv = value();
      const auto eq = kv.find('=');
      if (eq == std::string::npos) {
        std::cerr << "pbf_run: --set expects key=value, got '" << kv << "'\n";
        return 2;
      }
      overrides += kv.substr(0, eq) + ": " + kv.substr(eq + 1) + "\n";
    }
    else if (a == "-h" || a == "--help") {
      std::cout << "usage: pbf_run [scene] [--seconds S] [--spacing D] [--max-particles N] [--scenes-dir DIR] [--set solver_key=value]... [--track-wrenches]\n";
      return 0;
    } else if (!a.empty() && a[0] == '-') {
      std::cerr << "pbf_run: unknown option " << a << "\n";
      return 2;
    } else scene_name = a;
  }

  try {
    pbf::Scene scene = pbf::loadSceneFile(pbf::resolveScenePath(scene_name, scenes_dir));
    if (spacing > 0.0f) scene.solver.particle_spacing = spacing;
    if (!overrides.empty()) pbf::applySolverYaml(overrides, "--set", scene.solver);
    // Counted before anything is allocated, as the node does: a fine spacing must not take
    // the machine's memory first (--spacing 1e-5 grew by 3 GB a second).
    std::string why = scene.validate();
    if (why.empty()) why = scene.checkParticleCount(max_particles, "--max-particles");
    if (!why.empty()) {
      std::cerr << "pbf_run: " << why << "\n";
      return 2;
    }
    pbf::PbfSolver solver;
    pbf::setUpSolver(scene, solver);
    pbf::FloatingBodies floating = pbf::makeFloatingBodies(scene);
    // Emitters at their scene poses (no tf here), drains; no particle limit beyond memory's.
    pbf::FluidSources sources(scene.emitters, scene.drains, solver.size());
    solver.setWrenchTracking(track_wrenches);
    std::printf("pbf_run: scene '%s' (%s), %zu particles, spacing %.4f m, simulating %.2f s\n",
                scene.name.c_str(), scene.source.c_str(), solver.size(),
                scene.solver.particle_spacing, seconds);
    std::printf("%8s %7s %7s %5s %9s %9s %8s %10s %8s\n", "t[s]", "steps", "dt[ms]", "iter",
                "avgErr%", "maxErr%", "vmax", "Ekin[J]", "ms/step");
    // The particles' mean height, at the start and at the end: its drop is the fluid's
    // compaction (pbf::meanHeightAboveFloor).
    const double start_mean_height = pbf::meanHeightAboveFloor(solver.positions(), scene.container);
    const auto wall0 = std::chrono::steady_clock::now();
    double next_print = 0.0, step_ms = 0.0;
    int steps_since = 0, nan_retries = 0;
    long long total_iterations = 0;
    long long total_density_checks = 0, total_stopped_early = 0;
    while (solver.time() < seconds - 1e-9) {
      floating.prepare(solver);
      const pbf::StepStats st = solver.step();
      if (!st.failed) {
        floating.afterStep(solver, st.dt);
        sources.afterStep(solver, st.dt, std::size_t(-1));
      }
      step_ms += st.times.total_ms;
      ++steps_since;
      nan_retries += st.nan_retries;
      total_iterations += st.iterations;
      total_density_checks += st.density_checks;
      total_stopped_early += st.density_checks_stopped_early;
      if (st.failed) {
        std::fprintf(stderr, "pbf_run: step failed even at the smallest dt\n");
        return 1;
      }
      if (solver.time() >= next_print - 1e-9) {
        std::printf("%8.3f %7llu %7.3f %5d %9.3f %9.3f %8.3f %10.4f %8.2f\n", solver.time(),
                    static_cast<unsigned long long>(solver.stepCount()), st.dt * 1e3, st.iterations,
                    st.avg_density_error * 100, st.max_density_error * 100, st.max_speed,
                    st.kinetic_energy, step_ms / steps_since);
        std::fflush(stdout);
        next_print += 0.1;
        step_ms = 0.0;
        steps_since = 0;
      }
    }
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    double sum_v2 = 0.0;
    for (const auto& vel : solver.velocities()) sum_v2 += vel.squaredNorm();
    // Close pairs (< d/2) measure clumping: a fluid at rest density has none.
    std::size_t close_pairs = 0;
    {
      const float d = scene.solver.particle_spacing;
      pbf::NeighborGrid grid;
      const auto& order = grid.build(solver.positions(), 0.5f * d);
      std::vector<Eigen::Vector3f> sorted(order.size());
      for (std::size_t k = 0; k < order.size(); ++k) sorted[k] = solver.positions()[order[k]];
      grid.findNeighbors(sorted, 0.5f * d);
      close_pairs = grid.indices().size() / 2;
    }
    std::printf("pbf_run: final free-surface height %.4f m, rms speed %.4f m/s, pairs closer than d/2: %zu\n",
                pbf::freeSurfaceHeight(solver.positions(), scene.solver.particle_spacing, scene.container),
                std::sqrt(sum_v2 / std::max<std::size_t>(solver.size(), 1)), close_pairs);
    const double end_mean_height = pbf::meanHeightAboveFloor(solver.positions(), scene.container);
    std::printf("pbf_run: mean particle height above the floor %.5f m (%.5f m at the start: %+.3f %%)\n",
                end_mean_height, start_mean_height, 100.0 * (end_mean_height / start_mean_height - 1.0));
    std::printf("pbf_run: %.2f s simulated in %.2f s wall (real-time factor %.2f), %llu steps, "
                "%d NaN retries\n",
                solver.time(), wall, solver.time() / wall,
                static_cast<unsigned long long>(solver.stepCount()), nan_retries);
    const double steps = static_cast<double>(std::max<std::uint64_t>(solver.stepCount(), 1));
    std::printf("pbf_run: %.2f constraint iterations per step\n", static_cast<double>(total_iterations) / steps);
    if (scene.solver.gauss_seidel && scene.solver.density_tolerance > 0.0f)
      std::printf("pbf_run: %.2f density measurements per step (the sweeps' stop test), %.2f of them "
                  "stopped once the part measured failed it\n",
                  static_cast<double>(total_density_checks) / steps, static_cast<double>(total_stopped_early) / steps);
    if (!scene.emitters.empty() || !scene.drains.empty())
      std::printf("pbf_run: %zu particles = %zu at start + %llu emitted - %llu drained\n", solver.size(),
                  sources.initialParticles(), static_cast<unsigned long long>(sources.emitted()),
                  static_cast<unsigned long long>(sources.drained()));
    for (const auto& [index, body] : floating.bodies()) {
      const Eigen::Vector3f p = body.shape().pose.translation();
      std::printf("pbf_run: floating obstacle %zu ('%s') at (%.4f, %.4f, %.4f) m, speed %.4f m/s\n",
                  index, scene.obstacles[index].frame.c_str(), p.x(), p.y(), p.z(),
                  body.linearVelocity().norm());
    }
    if (solver.wrenches().valid) {
      const pbf::Wrench& c = solver.wrenches().container;
      std::printf("pbf_run: last step's force on the container (%.3f, %.3f, %.3f) N\n", c.force.x(),
                  c.force.y(), c.force.z());
      for (std::size_t k = 0; k < solver.wrenches().obstacles.size(); ++k) {
        const pbf::Wrench& w = solver.wrenches().obstacles[k];
        std::printf("pbf_run: ... on obstacle %zu (%.3f, %.3f, %.3f) N\n", k, w.force.x(), w.force.y(),
                    w.force.z());
      }
    }
  } catch (const std::exception& e) {
    std::cerr << "pbf_run: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
