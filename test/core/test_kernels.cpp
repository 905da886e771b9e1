// Kernels (eq 8-9) and the constraint gradient (eq 7) against numerical integration and
// finite differences.

#include <gtest/gtest.h>

#include <random>

#include "pbf_ros/core/Kernels.h"

namespace {

constexpr double kPi = 3.14159265358979323846;

TEST(Kernels, Poly6IntegratesToOneOverItsSupport) {
  for (float h : {0.04f, 1.0f}) {
    const pbf::Kernels k(h);
    // Radially symmetric: integral = 4 pi int_0^h W(r) r^2 dr (midpoint rule, fine grid).
    const int n = 20000;
    double integral = 0.0;
    for (int s = 0; s < n; ++s) {
      const double r = (s + 0.5) * h / n;
      integral += 4.0 * kPi * k.poly6(static_cast<float>(r * r)) * r * r * (h / n);
    }
    EXPECT_NEAR(integral, 1.0, 1e-4) << "h = " << h;
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
// exact gradient of C_i = sum_j m W_ij / rho0 - 1 when C is built from the same kernel. (PBF
// then uses Poly6 for rho and Spiky for the gradient, as Mueller et al. 2003 do: that
// mismatch is the method's, not eq 7's.) Checked with the Spiky kernel for both.
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

#include "pbf_ros/core/Boundaries.h"

namespace {

// The wall's density fraction F(s) must equal the Poly6 kernel integrated over the
// half-space beyond a plane at distance s, and the wall gradient must be dF/dp.
TEST(WallDensity, FractionEqualsKernelIntegralBeyondThePlaneAndGradientIsItsDerivative) {
  const float h = 0.04f;
  const pbf::Kernels k(h);
  const Eigen::AlignedBox3f box(Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(1, 1, 1));
  const pbf::BoxWallDensity walls(box, h);
  EXPECT_NEAR(walls.fractionBeyond(0.0f), 0.5, 1e-4);
  EXPECT_EQ(walls.fractionBeyond(h), 0.0f);
  for (float s : {0.005f, 0.01f, 0.02f, 0.035f}) {
    // Numerical integral over z in [s, h] of the kernel's mass in each plane.
    const int n = 4000;
    double f = 0.0;
    for (int a = 0; a < n; ++a) {
      const double z = s + (a + 0.5) * (h - s) / n;
      // plane integral of Poly6 at height z: int_0^sqrt(h^2-z^2) W 2 pi rho d rho
      const int m = 400;
      const double rmax = std::sqrt(h * h - z * z);
      double plane = 0.0;
      for (int b = 0; b < m; ++b) {
        const double rho = (b + 0.5) * rmax / m;
        plane += k.poly6(float(rho * rho + z * z)) * 2.0 * kPi * rho * (rmax / m);
      }
      f += plane * (h - s) / n;
    }
    EXPECT_NEAR(walls.fractionBeyond(s), f, 2e-4) << "s = " << s;
    // Particle at distance s from the floor (z = s), far from the other walls.
    float frac = 0.0f;
    Eigen::Vector3f grad = Eigen::Vector3f::Zero();
    ASSERT_TRUE(walls.accumulate(Eigen::Vector3f(0.5f, 0.5f, s), frac, grad));
    EXPECT_NEAR(frac, walls.fractionBeyond(s), 1e-6);
    const float ds = 1e-4f;
    const double fd = (walls.fractionBeyond(s + ds) - walls.fractionBeyond(s - ds)) / (2 * ds);
    EXPECT_NEAR(grad.z(), fd, 1e-2 * std::abs(fd) + 1e-3);
    EXPECT_EQ(grad.x(), 0.0f);
  }
  float frac = 0.0f;
  Eigen::Vector3f grad = Eigen::Vector3f::Zero();
  EXPECT_FALSE(walls.accumulate(Eigen::Vector3f(0.5f, 0.5f, 0.5f), frac, grad));
}

}  // namespace
