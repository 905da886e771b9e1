#pragma once
// Martin & Moyce (1952) surge-front data and the error of a simulated front against it.
// Non-dimensional: T = t sqrt(2 g / a), Z = front / a.

#include <string>
#include <vector>

namespace pbf_bench {

struct FrontCurve {
  std::vector<double> T, Z;  // T ascending
};

// Reads "T,Z" rows; lines starting with '#' and the header are skipped. Throws
// std::runtime_error naming the file and line for anything unreadable.
FrontCurve loadFrontCurve(const std::string& path);

// Z of a curve at T, linear between samples, clamped at the ends.
double interpolate(const FrontCurve& curve, double T);

// RMS of Z_sim(T - shift) - Z_ref(T) over the reference points with T <= t_max (in units
// of a). A positive shift delays the simulation, as the experiment's gate release does.
double frontRms(const FrontCurve& sim, const FrontCurve& ref, double shift, double t_max);

// The shift in [0, max_shift] (steps of 0.01) that minimises frontRms.
double bestShift(const FrontCurve& sim, const FrontCurve& ref, double t_max, double max_shift);

}  // namespace pbf_bench
