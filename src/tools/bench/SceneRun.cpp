#include "bench/SceneRun.h"

#include <cstdio>
#include <ctime>

#include "bench/Progress.h"
#include "pbf_ros/core/SceneSetup.h"

namespace pbf_bench {

std::unique_ptr<pbf::PbfSolver> makeSolver(const pbf::Scene& scene) {
  auto solver = std::make_unique<pbf::PbfSolver>();
  pbf::setUpSolver(scene, *solver);  // parameters, container, obstacles, particles
  return solver;
}

RunTotals runUntil(pbf::PbfSolver& solver, double t_end, const StepObserver& observe,
                   Progress* progress) {
  RunTotals totals;
  const double t0 = solver.time();
  const std::clock_t cpu0 = std::clock();
  while (solver.time() < t_end - 1e-9) {
    const pbf::StepStats st = solver.step();
    totals.step_wall_seconds += st.times.total_ms * 1e-3;
    totals.nan_retries += st.nan_retries;
    if (st.failed) {
      totals.failed = true;
      break;
    }
    ++totals.steps;
    totals.iterations += st.iterations;
    totals.capped_steps += st.iteration_cap_reached ? 1 : 0;
    if (observe) observe(solver, st);
    if (progress) {
      char detail[64];
      std::snprintf(detail, sizeof detail, "t=%.3f s, %lld steps", solver.time(), totals.steps);
      progress->update((solver.time() - t0) / std::max(1e-9, t_end - t0), detail);
    }
  }
  totals.sim_seconds = solver.time() - t0;
  totals.cpu_seconds = double(std::clock() - cpu0) / CLOCKS_PER_SEC;
  return totals;
}

}  // namespace pbf_bench
