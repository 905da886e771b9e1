#pragma once
// One hydrostatic-tank run: water at rest should stay at rest density, at the level its
// volume implies, and still. Errors are measured over the last third of the run (after
// the lattice has settled under gravity).

#include "bench/SceneRun.h"
#include "pbf_ros/core/Scene.h"

namespace pbf_bench {

struct HydrostaticResult {
  std::size_t particles = 0;
  double avg_density_error = 0.0;  // mean over the window of the per-step average
  double max_density_error = 0.0;  // max over the window of the per-step maximum
  double height_loss = 0.0;        // (H_volume - H_surface) / H_volume at the end
  double residual_speed_max = 0.0; // [m/s] at the end
  double residual_speed_rms = 0.0; // [m/s] at the end
  double mean_iterations = 0.0;
  RunTotals totals;
};

HydrostaticResult runHydrostatic(const pbf::Scene& scene, double settle_seconds, Progress* progress);

}  // namespace pbf_bench
