#pragma once
// Issue 5, part 1: the dam break against Martin & Moyce at three resolutions, plus the
// shipped default scene (full tank depth) for the accuracy target.
// Writes dambreak_front.csv (Z(T) per run) and dambreak_summary.csv (RMS per run).

#include "bench/BenchOptions.h"

namespace pbf_bench {

void runDamBreakStudy(const BenchOptions& options);

}  // namespace pbf_bench
