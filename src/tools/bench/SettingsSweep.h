#pragma once
// Issue 5, parts 2 and 3: one sweep over solver settings, each run on the hydrostatic tank
// (density error, level loss, residual speed) and on the dam break (front RMS against
// Martin & Moyce, and deviation from a converged reference run), with wall-clock seconds
// per simulated second for both. The "iterations" and "tolerance" groups are the
// hydrostatic study; all rows together are the Pareto data. Writes sweep.csv.

#include "bench/BenchOptions.h"

namespace pbf_bench {

void runSettingsSweep(const BenchOptions& options);

}  // namespace pbf_bench
