#pragma once
// Running a scene for a stretch of simulated time, with the totals a benchmark needs.

#include <functional>
#include <memory>
#include <string>

#include "pbf_ros/core/PbfSolver.h"
#include "pbf_ros/core/Scene.h"

namespace pbf_bench {

class Progress;

std::unique_ptr<pbf::PbfSolver> makeSolver(const pbf::Scene& scene);

struct RunTotals {
  double sim_seconds = 0.0;
  double step_wall_seconds = 0.0;  // sum of the solver's own step times (wall clock)
  // Process CPU time over the run (all threads): less sensitive than wall time to other
  // processes on a shared machine, so both are reported.
  double cpu_seconds = 0.0;
  long long steps = 0;
  long long iterations = 0;       // summed over steps
  long long capped_steps = 0;     // steps whose solve stopped at max_iterations above the tolerance
  int nan_retries = 0;
  bool failed = false;             // a step failed even at the smallest dt
  double wallPerSimSecond() const { return sim_seconds > 0 ? step_wall_seconds / sim_seconds : 0.0; }
  double cpuPerSimSecond() const { return sim_seconds > 0 ? cpu_seconds / sim_seconds : 0.0; }
};

using StepObserver = std::function<void(const pbf::PbfSolver&, const pbf::StepStats&)>;

// Steps until solver.time() >= t_end (solver.step(): the scene's own dt rule), calling
// observe after every step. Stops early on a failed step. progress may be null.
RunTotals runUntil(pbf::PbfSolver& solver, double t_end, const StepObserver& observe,
                   Progress* progress);

}  // namespace pbf_bench
