#pragma once
// Issue 5, part 4: milliseconds per step against particle count (10k -> 320k) and
// threads (1, 2), with the log-log slope. Writes scaling.csv.

#include <vector>

#include "bench/BenchOptions.h"
#include "pbf_ros/core/Scene.h"

namespace pbf_bench {

void runScalingStudy(const BenchOptions& options);

// The dam-break column (0.4 x 0.5 x 0.8 m = 0.16 m^3) at the spacing giving about `count`
// particles, timed once it flows (from 0.25 s simulated, as pbf_step_benchmark; until
// session 37 the third to seventh steps after release, whose state depended on how the
// lattice met the walls at each spacing). 4 fixed iterations, fixed dt 1/400 s (as
// pbf_step_benchmark); the options' --set overrides applied last.
pbf::Scene scalingScene(const BenchOptions& options, int count);

// Least-squares slope of log(y) against log(x).
double logLogSlope(const std::vector<double>& x, const std::vector<double>& y);

}  // namespace pbf_bench
