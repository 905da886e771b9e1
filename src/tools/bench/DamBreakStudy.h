#pragma once
// Issue 5, part 1: the dam break against Martin & Moyce at three resolutions, plus the
// shipped default scene (full tank depth) for the accuracy target.
// Writes dambreak_front.csv (Z(T) per run) and dambreak_summary.csv (RMS per run).

#include <string>
#include <vector>

#include "bench/BenchOptions.h"

namespace pbf_bench {

struct DamBreakResolution {
  std::string label;
  float spacing;
  float depth;          // tank depth across y [m]; 0 = the scene's own (0.5 m)
  bool settled = true;  // start from the settled column (false: the scene's lattice)
};

// The runs of the study. Every spacing tiles the column (a x 2a) and the tank's depth
// exactly: the lattice is centred in its box with floor(size / d) particles per axis, so a
// spacing that does not divide them leaves gaps the water spreads into, and the column runs
// lower. 0.0126 m (four times the medium slab's particles) fits 31 x 63 x 15 particles
// where 32 x 64 x 16 belong: 8 % of the water was missing, and its front lagged.
std::vector<DamBreakResolution> damBreakResolutions(bool quick);

void runDamBreakStudy(const BenchOptions& options);

// The resolution study carried further (`pbf_bench --only convergence`): the same slab at
// a/d = 10, 20, 32, 48 and 64, to show where the fitted gate delay and the front converge.
// Writes dambreak_convergence_front.csv and dambreak_convergence_summary.csv (~10 min on 2
// cores: the finest run holds 262 144 particles).
std::vector<DamBreakResolution> damBreakConvergence();
void runDamBreakConvergence(const BenchOptions& options);

}  // namespace pbf_bench
