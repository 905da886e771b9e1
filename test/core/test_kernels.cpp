// Kernels (eq 8-9) and the constraint gradient (eq 7) against numerical integration and
// finite differences.

#include <gtest/gtest.h>

#include <random>

#include "pbf_ros/core/Kernels.h"

namespace {

constexpr double kPi = 3.14159265358979323846;

TEST(Kernels, Poly6AndSpikyIntegrateToOneOverTheirSupport) {
  for (float h : {0.04f, 1.0f}) {
    const pbf::Kernels k(h);
    // Radially symmetric: integral = 4 pi int_0^h W(r) r^2 dr (midpoint rule, fine grid).
    const int n = 20000;
    double integral = 0.0, spiky_integral = 0.0;
    for (int s = 0; s < n; ++s) {
      const double r = (s + 0.5) * h / n;
      integral += 4.0 * kPi * k.poly6(static_cast<float>(r * r)) * r * r * (h / n);
      spiky_integral += 4.0 * kPi * k.spiky(static_cast<float>(r)) * r * r * (h / n);
    }
    EXPECT_NEAR(integral, 1.0, 1e-4) << "h = " << h;
    EXPECT_NEAR(spiky_integral, 1.0, 1e-4) << "h = " << h;
    EXPECT_EQ(k.poly6(h * h), 0.0f);
    EXPECT_EQ(k.poly6(4.0f * h * h), 0.0f);
  }
}

TEST(Kernels, SpikyGradientMatchesFiniteDifferenceOfSpiky) {
  const float h = 0.1f;
  const pbf::Kernels k(h);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-h, h);
  int tested = 0;
  while (tested < 200) {
    const Eigen::Vector3d r(u(rng), u(rng), u(rng));
    const double len = r.norm();
    if (len > 0.95 * h || len < 0.05 * h) continue;
    const Eigen::Vector3f g = k.spikyGradient(r.cast<float>(), static_cast<float>(len));
    const double step = 1e-4 * h;
    for (int a = 0; a < 3; ++a) {
      Eigen::Vector3d rp = r, rm = r;
      rp[a] += step;
      rm[a] -= step;
      const double fd = (double(k.spiky(float(rp.norm()))) - k.spiky(float(rm.norm()))) / (2 * step);
      EXPECT_NEAR(g[a], fd, 2e-3 * std::abs(k.spiky_grad_coef) * h * h) << "axis " << a;
    }
    ++tested;
  }
}

// eq 7: grad_{p_k} C_i = (m / rho0) { sum_j grad W_ij (k = i); -grad W_ij (k = j) } is the
// exact gradient of C_i = sum_j m W_ij / rho0 - 1 when C is built from the same kernel, as
// the solver does (Spiky for both; the seed's Poly6 density with a Spiky gradient is not,
// see Kernels.h).
TEST(Kernels, ConstraintGradientMatchesFiniteDifferenceOfC) {
  const float h = 0.04f, mass = 0.008f, rho0 = 1000.0f;
  const pbf::Kernels k(h);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.9 * h, 0.9 * h);
  std::vector<Eigen::Vector3d> p(12);
  p[0].setZero();
  for (std::size_t j = 1; j < p.size(); ++j) p[j] = Eigen::Vector3d(u(rng), u(rng), u(rng));
  auto constraint = [&](const std::vector<Eigen::Vector3d>& q) {
    double rho = 0.0;
    for (std::size_t j = 1; j < q.size(); ++j) rho += mass * k.spiky(float((q[0] - q[j]).norm()));
    return rho / rho0 - 1.0;
  };
  const double step = 1e-5;
  for (std::size_t kk = 0; kk < p.size(); ++kk) {
    Eigen::Vector3d analytic = Eigen::Vector3d::Zero();
    for (std::size_t j = 1; j < p.size(); ++j) {
      const Eigen::Vector3d r = p[0] - p[j];
      const Eigen::Vector3d g = (mass / rho0) * k.spikyGradient(r.cast<float>(), float(r.norm())).cast<double>();
      if (kk == 0) analytic += g;
      else if (kk == j) analytic -= g;
    }
    for (int a = 0; a < 3; ++a) {
      auto qp = p, qm = p;
      qp[kk][a] += step;
      qm[kk][a] -= step;
      const double fd = (constraint(qp) - constraint(qm)) / (2 * step);
      EXPECT_NEAR(analytic[a], fd, 1e-3 * std::max(1.0, std::abs(fd))) << "k=" << kk << " axis " << a;
    }
  }
}

}  // namespace

#include "pbf_ros/core/LatticeBoundary.h"

namespace {

// The continuum fractions the curvature correction uses: a ball's must equal the density
// kernel (Spiky) integrated over the ball (numerically here), and tend to the half-space's (whose
// value at the plane is 1/2) as the radius grows.
TEST(WallDensity, ContinuumBallAndHalfSpaceFractionsAreKernelIntegrals) {
  const double h = 0.04;
  const pbf::Kernels k(static_cast<float>(h));
  EXPECT_NEAR(pbf::continuumHalfSpaceFraction(0.0, h), 0.5, 1e-9);
  EXPECT_EQ(pbf::continuumHalfSpaceFraction(h, h), 0.0);
  for (double radius : {0.02, 0.08, 0.5})
    for (double s : {0.0, 0.01, 0.025}) {
      // Midpoint rule over a grid covering the kernel's support (fine: the kernel's cusp at
      // the particle lies on the ball's surface when s = 0).
      const int n = 160;
      const double step = 2.0 * h / n;
      double integral = 0.0;
      for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b)
          for (int c = 0; c < n; ++c) {
            const Eigen::Vector3d x(-h + (a + 0.5) * step, -h + (b + 0.5) * step, -h + (c + 0.5) * step);
            // Ball centre at distance radius + s from the particle (origin), along +z.
            if ((x - Eigen::Vector3d(0, 0, radius + s)).norm() > radius) continue;
            integral += k.spiky(static_cast<float>(x.norm())) * step * step * step;
          }
      EXPECT_NEAR(pbf::continuumBallFraction(s, radius, h), integral, 3e-3)
          << "radius " << radius << " s " << s;
    }
  EXPECT_NEAR(pbf::continuumBallFraction(0.01, 1e4, h), pbf::continuumHalfSpaceFraction(0.01, h), 1e-6);
}

}  // namespace
