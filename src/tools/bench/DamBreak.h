#pragma once
// One dam-break run measured against Martin & Moyce: the surge-front curve Z(T), its RMS
// error with and without a gate-release time shift, and height profiles at T = 1, 2, 3
// (to compare runs of the same scene with each other).

#include <string>
#include <vector>

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
  std::vector<std::vector<double>> profiles;  // h(x)/a at profileTimes(), bins of a/10
  RunTotals totals;
};

DamBreakResult runDamBreak(const pbf::Scene& scene, const FrontCurve& reference,
                           Progress* progress);

// RMS difference of two runs' height profiles (in units of a) over all profile times.
double profileDeviation(const DamBreakResult& run, const DamBreakResult& reference);

}  // namespace pbf_bench
