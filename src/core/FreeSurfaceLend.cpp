#include "FreeSurfaceLend.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "pbf_ros/core/LatticeBoundary.h"

namespace pbf {

namespace {

// The density kernel (Spiky, Kernels.h) in units of d (support H = h / d) over the
// half-space beyond a plane at distance s from the particle (continuumHalfSpaceFraction, the
// walls' continuum). Its integral over the plane itself is continuumPlaneIntegral.
double beyondPlane(double s, double H) { return continuumHalfSpaceFraction(std::max(s, 0.0), H); }

// The depth s in [0, H] whose plane integral is p (decreasing in s): bisection.
double depthFor(double p, double H) {
  double lo = 0.0, hi = H;
  for (int k = 0; k < 60; ++k) {
    const double mid = 0.5 * (lo + hi);
    (continuumPlaneIntegral(mid, H) > p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

FreeSurfaceLend::FreeSurfaceLend(float spacing, float support_radius) : d_(spacing), h_(support_radius) {
  if (!(spacing > 0.0f) || !(support_radius >= spacing))
    throw std::invalid_argument("FreeSurfaceLend: needs spacing > 0 and support radius >= spacing");
  const double H = static_cast<double>(support_radius) / spacing;
  const double S = latticeKernelSum(H);
  // The start lattice's top layer: the particle at the origin with the lattice below it.
  const int n = static_cast<int>(std::ceil(H));
  double below = 0.0, gradient = 0.0;
  const double coef = 15.0 / (M_PI * std::pow(H, 6.0));
  for (int z = -n; z <= 0; ++z)
    for (int y = -n; y <= n; ++y)
      for (int x = -n; x <= n; ++x) {
        const double r = std::sqrt(double(x * x + y * y + z * z));
        if (r >= H) continue;
        below += coef * std::pow(H - r, 3.0);
        if (r > 0.0) gradient += 3.0 * coef * (H - r) * (H - r) * (-z) / r;  // |dW/dr| along z
      }
  lattice_deficit_ = static_cast<float>(1.0 - below / S);
  lattice_gradient_ = static_cast<float>(gradient / S);
  // A kernel that reaches no lattice neighbour (h = d) misses nothing at a surface.
  const double continuum = beyondPlane(depthFor(gradient, H), H) / S;
  const double calibration = continuum > 0.0 ? lattice_deficit_ / continuum : 0.0;
  // Tabulated over |grad C| d in [0, Pi(0) / S], the largest a plane surface gives.
  constexpr int kSteps = 1024;
  const double top = continuumPlaneIntegral(0.0, H) / S;
  step_ = static_cast<float>(top / kSteps);
  table_.resize(kSteps + 1);
  for (int k = 0; k <= kSteps; ++k)
    table_[k] = static_cast<float>(calibration * beyondPlane(depthFor(k * top / kSteps * S, H), H) / S);
}

float FreeSurfaceLend::fraction(float grad_norm) const {
  const float x = grad_norm * d_ / step_;  // table steps
  if (!(x > 0.0f)) return 0.0f;            // NaN stays out: no lend
  const auto last = static_cast<float>(table_.size() - 1);
  if (x >= last) return table_.back();
  const int k = static_cast<int>(x);
  const float t = x - static_cast<float>(k);
  return table_[k] + t * (table_[k + 1] - table_[k]);
}

}  // namespace pbf
