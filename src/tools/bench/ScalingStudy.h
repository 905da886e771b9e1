#pragma once
// Issue 5, part 4: milliseconds per step against particle count (10k -> 320k) and
// threads (1, 2), with the log-log slope. Writes scaling.csv.

#include <vector>

#include "bench/BenchOptions.h"

namespace pbf_bench {

void runScalingStudy(const BenchOptions& options);

// Least-squares slope of log(y) against log(x).
double logLogSlope(const std::vector<double>& x, const std::vector<double>& y);

}  // namespace pbf_bench
