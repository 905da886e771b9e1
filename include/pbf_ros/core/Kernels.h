#pragma once
// SPH kernels. The density constraint uses one kernel, Spiky, for the density (eq 8) and for
// its gradient (eq 9), so that the correction lies along grad C, normal to the constraint's
// level set. The seed (Mueller et al. 2003, Macklin & Mueller 2013) sums the density with
// Poly6 but takes the Spiky gradient: that gradient is not the gradient of the density it
// corrects, the correction then has a part along the level set, and that part does work:
// a tank at rest never comes to rest (doc/calibration.md). Poly6 stays the smoothing
// kernel of XSPH and s_corr, which are filters, not the constraint. Constants are
// precomputed once per support radius h.

#include <Eigen/Core>
#include <cmath>

namespace pbf {

struct Kernels {
  explicit Kernels(float support_radius)
      : h(support_radius),
        h2(support_radius * support_radius),
        poly6_coef(315.0f / (64.0f * static_cast<float>(M_PI) * std::pow(support_radius, 9.0f))),
        spiky_coef(15.0f / (static_cast<float>(M_PI) * std::pow(support_radius, 6.0f))),
        spiky_grad_coef(-45.0f / (static_cast<float>(M_PI) * std::pow(support_radius, 6.0f))) {}

  // W(r) for r^2 = r2; zero outside the support.
  float poly6(float r2) const {
    if (r2 >= h2) return 0.0f;
    const float d = h2 - r2;
    return poly6_coef * d * d * d;
  }

  // grad_i W_spiky(p_i - p_j) for r = p_i - p_j with length rlen > 0; zero outside the
  // support. The caller handles rlen == 0 (coincident particles have no direction).
  Eigen::Vector3f spikyGradient(const Eigen::Vector3f& r, float rlen) const {
    if (rlen >= h) return Eigen::Vector3f::Zero();
    const float d = h - rlen;
    return (spiky_grad_coef * d * d / rlen) * r;
  }

  // The Spiky kernel itself, W = 15/(pi h^6) (h - r)^3: the density kernel.
  float spiky(float rlen) const {
    if (rlen >= h) return 0.0f;
    const float d = h - rlen;
    return spiky_coef * d * d * d;
  }

  float h, h2, poly6_coef, spiky_coef, spiky_grad_coef;
};

}  // namespace pbf
