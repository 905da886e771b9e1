#pragma once
// Issue 9, item 4: iterations to reach an average density error of 0.1 % and 0.01 %, with
// and without the warm start (and, cold, to the error the warm run reached; and warm with
// the Chebyshev acceleration), at dt = 1/240, 1/120 and 1/60 s, on the hydrostatic tank and
// in the dam break; and what that costs per simulated second. Writes warm_start.csv.

#include "bench/BenchOptions.h"

namespace pbf_bench {

void runWarmStartStudy(const BenchOptions& options);

}  // namespace pbf_bench
