#pragma once
// One dam-break run measured against Martin & Moyce: the surge-front curve Z(T), its RMS
// error with and without a gate-release time shift, and height profiles at T = 1, 2, 3
// (to compare runs of the same scene with each other).

#include <string>
#include <vector>

#include <Eigen/Core>

#include "bench/MartinMoyce.h"
#include "bench/SceneRun.h"
#include "pbf_ros/core/Scene.h"

namespace pbf_bench {

// The error is taken over the tabulated T <= kFrontRmsTMax (the target range);
// the run goes a little beyond so the last data point is covered.
constexpr double kFrontRmsTMax = 3.0;
constexpr double kDamBreakTEnd = 3.35;
constexpr double kMaxGateShift = 0.4;
const std::vector<double>& profileTimes();  // T at which height profiles are taken

struct DamBreakResult {
  std::size_t particles = 0;
  double a = 0.0;                // column width [m]
  FrontCurve curve;              // simulated Z(T)
  double rms_no_shift = 0.0;     // [a], T <= kFrontRmsTMax
  double shift = 0.0;            // best gate-release shift in [0, kMaxGateShift]
  double rms_shifted = 0.0;      // [a] at that shift
  // Sensitivity of the front definition: the unshifted RMS and the fitted shift when a slab
  // needs a quarter of a particle row, or a full row, instead of half a row to count as fluid.
  double rms_no_shift_quarter_row = 0.0, rms_no_shift_full_row = 0.0;
  double shift_quarter_row = 0.0, shift_full_row = 0.0;
  // The front of surgeFrontSliding (no slab quantisation): its curve and the same figures.
  FrontCurve curve_sliding;
  double rms_no_shift_sliding = 0.0, shift_sliding = 0.0, rms_shifted_sliding = 0.0;
  std::vector<std::vector<double>> profiles;  // h(x)/a at profileTimes(), bins of a/10
  RunTotals totals;
};

// Water at rest behind the gate, as in the experiment: the scene's column settled under
// gravity in a box of its own (the tank cut at the column's face), by kinematic relaxation
// (velocities zeroed after every step; dt 1/240 s, density tolerance 0.05 %, 0.5 s).
// Without it the run starts from the lattice, whose Poly6 density is ~1.7 % above rest:
// the projection expands it in the first steps and launches the column's top upwards, the
// faster the smaller dt and the more iterations (see the report).
using Positions = std::vector<Eigen::Vector3f>;
Positions settledColumn(const pbf::Scene& scene, Progress* progress);

// start: initial positions (e.g. settledColumn); null = the scene's lattice.
DamBreakResult runDamBreak(const pbf::Scene& scene, const FrontCurve& reference,
                           Progress* progress, const Positions* start = nullptr);

// RMS difference of two runs' height profiles (in units of a) over all profile times.
double profileDeviation(const DamBreakResult& run, const DamBreakResult& reference);

}  // namespace pbf_bench
