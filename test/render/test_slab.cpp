// A flat slab of particles seen obliquely: its normals must be the slab's normal within a
// few degrees, and what error there is must not line up with the image axes (the streaks
// that separable depth filters leave). The default narrow-range filter is held to the
// bounds; the bilateral option's numbers are printed for comparison.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <vector>

#include "RenderTestSupport.h"

namespace {

constexpr float kSpacing = 0.02f;
constexpr float kRadius = 0.5f * kSpacing;
constexpr int kWindow = 128;  // side of the square analysed for streaks (pixels)

pbf::RenderCamera slabCamera() {
  pbf::RenderCamera camera;
  camera.width = 320;
  camera.height = 240;
  camera.vertical_fov = 50.0f * static_cast<float>(M_PI) / 180.0f;
  // 0.7 m from the slab's centre, 50 degrees above it, turned 17 degrees about z so the
  // particle lattice lines up with neither the image axes nor their diagonals. The slab
  // (2.4 m square) fills the whole image.
  const float yaw = 17.0f * static_cast<float>(M_PI) / 180.0f;
  const float elevation = 50.0f * static_cast<float>(M_PI) / 180.0f;
  const Eigen::Vector3f target(0.0f, 0.0f, 0.1f);
  const Eigen::Vector3f eye =
      target + 0.7f * Eigen::Vector3f(-std::cos(elevation) * std::cos(yaw),
                                      -std::cos(elevation) * std::sin(yaw), std::sin(elevation));
  camera.camera_to_world = pbf::lookAt(eye, target);
  return camera;
}

struct SlabErrors {
  double mean_deg = 0, p95_deg = 0;
  double axis_energy = 0, diagonal_energy = 0;  // of the normal error, see streakEnergies
  std::size_t compared = 0;
};

// Power spectrum of a kWindow^2 field (direct separable DFT; small enough not to matter).
std::vector<double> powerSpectrum(const std::vector<double>& field) {
  const int n = kWindow;
  std::vector<std::complex<double>> rows(field.size()), spectrum(field.size());
  for (int y = 0; y < n; ++y)
    for (int kx = 0; kx < n; ++kx) {
      std::complex<double> s = 0;
      for (int x = 0; x < n; ++x)
        s += field[y * n + x] * std::polar(1.0, -2.0 * M_PI * kx * x / n);
      rows[y * n + kx] = s;
    }
  for (int kx = 0; kx < n; ++kx)
    for (int ky = 0; ky < n; ++ky) {
      std::complex<double> s = 0;
      for (int y = 0; y < n; ++y) s += rows[y * n + kx] * std::polar(1.0, -2.0 * M_PI * ky * y / n);
      spectrum[ky * n + kx] = s;
    }
  std::vector<double> power(field.size());
  for (std::size_t i = 0; i < power.size(); ++i) power[i] = std::norm(spectrum[i]);
  return power;
}

// Streaks along an image axis put their energy on the other frequency axis; so compare the
// spectral energy within 10 degrees of the frequency axes with that within 10 degrees of
// the diagonals (equal areas). Isotropic error gives a ratio near 1. The lowest
// frequencies (|k| < 3) are left out: they hold the overall tilt, not texture.
void streakEnergies(const std::vector<double>& field, double& axis, double& diagonal) {
  const std::vector<double> power = powerSpectrum(field);
  const int n = kWindow;
  for (int ky = 0; ky < n; ++ky)
    for (int kx = 0; kx < n; ++kx) {
      const int fx = kx <= n / 2 ? kx : kx - n, fy = ky <= n / 2 ? ky : ky - n;
      if (fx * fx + fy * fy < 9) continue;
      double angle = std::atan2(std::abs(fy), std::abs(fx)) * 180.0 / M_PI;  // 0..90
      if (angle < 10.0 || angle > 80.0) axis += power[ky * n + kx];
      else if (std::abs(angle - 45.0) < 10.0) diagonal += power[ky * n + kx];
    }
}

SlabErrors renderSlab(pbf::DepthFilter filter, const std::string& name) {
  pbf::RenderOptions options;
  options.filter = filter;
  pbf::FluidRenderer renderer(pbf::createGlBackend("osmesa"), pbf_test::shaderDir(), options);
  const auto particles = pbf_test::latticeSlab(120, 120, 3, kSpacing, 0.1f - kRadius);
  const pbf::RenderCamera camera = slabCamera();
  pbf::RenderOutput out;
  renderer.render(particles, kRadius, camera, pbf_test::everything(), out);
  pbf_test::saveImages(name, out);

  // The true normal, world +z, in the optical frame.
  const Eigen::Vector3f truth = camera.camera_to_world.linear().transpose() * Eigen::Vector3f::UnitZ();
  SlabErrors e;
  std::vector<double> angles;
  const int margin = 16;  // the filter's reach: near the image border it has fewer taps
  for (int v = margin; v < out.height - margin; ++v)
    for (int u = margin; u < out.width - margin; ++u) {
      const Eigen::Vector3f n = pbf_test::normalAt(out, u, v);
      if (n.isZero()) continue;
      angles.push_back(pbf_test::angleDegrees(n, truth));
    }
  e.compared = angles.size();
  for (double a : angles) e.mean_deg += a;
  e.mean_deg /= std::max<std::size_t>(angles.size(), 1);
  std::sort(angles.begin(), angles.end());
  e.p95_deg = angles.empty() ? 0 : angles[angles.size() * 95 / 100];

  // Error field in the central window: the two components of (n - truth) across the view.
  const Eigen::Vector3f across = truth.cross(Eigen::Vector3f::UnitZ()).normalized();
  const Eigen::Vector3f along = truth.cross(across);
  std::vector<double> error_a(kWindow * kWindow), error_b(kWindow * kWindow);
  const int u0 = out.width / 2 - kWindow / 2, v0 = out.height / 2 - kWindow / 2;
  for (int y = 0; y < kWindow; ++y)
    for (int x = 0; x < kWindow; ++x) {
      const Eigen::Vector3f d = pbf_test::normalAt(out, u0 + x, v0 + y) - truth;
      error_a[y * kWindow + x] = d.dot(across);
      error_b[y * kWindow + x] = d.dot(along);
    }
  streakEnergies(error_a, e.axis_energy, e.diagonal_energy);
  streakEnergies(error_b, e.axis_energy, e.diagonal_energy);
  std::printf("[%s] %zu pixels: normal error mean %.2f deg, 95th percentile %.2f deg; "
              "error energy along image axes / along diagonals = %.2f; %.1f ms\n",
              name.c_str(), e.compared, e.mean_deg, e.p95_deg,
              e.axis_energy / std::max(e.diagonal_energy, 1e-30), out.timings.total);
  return e;
}

TEST(Slab, NarrowRangeNormalsAreFlatWithoutAxisAlignedStreaks) {
  const SlabErrors e = renderSlab(pbf::DepthFilter::NarrowRange, "slab_narrow_range");
  ASSERT_GT(e.compared, 40000u);  // the slab fills the view
  EXPECT_LT(e.mean_deg, 3.0);
  EXPECT_LT(e.p95_deg, 6.0);
  // No direction of the image is special: axis-aligned energy within 1.5x the diagonal one.
  EXPECT_LT(e.axis_energy, 1.5 * e.diagonal_energy);
}

TEST(Slab, BilateralOptionForComparison) {
  const SlabErrors e = renderSlab(pbf::DepthFilter::Bilateral, "slab_bilateral");
  ASSERT_GT(e.compared, 40000u);
  EXPECT_LT(e.mean_deg, 15.0);  // a sanity bound only; the numbers are for the log
}

}  // namespace
