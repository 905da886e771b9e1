#pragma once
// Issue 9: the hydrostatic tank at the shipped defaults, with dt halved, and at the spacing
// of the dam-break study's fine slab (0.0125 m, which tiles the tank: 32 x 32 x 24): the
// start-up (largest speed over the first 0.5 s of a fresh lattice), the level against the
// one the volume implies, and the density error. Writes tank.csv.

#include "bench/BenchOptions.h"

namespace pbf_bench {

void runTankStudy(const BenchOptions& options);

}  // namespace pbf_bench
