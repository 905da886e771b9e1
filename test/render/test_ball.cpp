// A ball of particles must render as a ball: depth close to the analytic sphere's and
// normals close to the sphere's normals, with the default narrow-range filter.

#include <gtest/gtest.h>

#include <cmath>

#include "RenderTestSupport.h"

namespace {

using pbf_test::angleDegrees;

struct BallErrors {
  double depth_rms = 0;        // metres
  double depth_mean = 0;       // metres, positive = rendered surface deeper than the sphere
  double depth_spread = 0;     // metres, RMS about the mean: the shape error
  double normal_mean_deg = 0;  // degrees
  std::size_t compared = 0, missing = 0;
};

// Compares against the sphere of radius `surface_radius` only where the analytic surface
// faces the camera at more than ~25 degrees (cos > 0.42): the silhouette band, where a
// depth step of one pixel is a large depth error and screen-space normals are known to be
// poor, is left out as the brief allows.
BallErrors compareWithSphere(const pbf::RenderCamera& camera, const pbf::RenderOutput& out,
                             const Eigen::Vector3f& centre, float surface_radius) {
  BallErrors e;
  double depth_sq = 0, depth_sum = 0, angle_sum = 0;
  const Eigen::Matrix3f world_to_camera = camera.camera_to_world.inverse().linear();
  const Eigen::Vector3f centre_camera = camera.camera_to_world.inverse() * centre;
  for (int v = 0; v < out.height; ++v)
    for (int u = 0; u < out.width; ++u) {
      const Eigen::Vector3f ray = pbf_test::pixelRay(camera, u, v);
      const float t = pbf_test::raySphere(camera, ray, centre, surface_radius);
      if (t < 0) continue;
      const Eigen::Vector3f hit = t * ray;
      const Eigen::Vector3f normal = (hit - centre_camera) / surface_radius;
      if (normal.dot(-ray) < 0.42f) continue;
      const float depth = out.depth[static_cast<std::size_t>(v) * out.width + u];
      if (!std::isfinite(depth)) {
        ++e.missing;
        continue;
      }
      depth_sq += (depth - hit.z()) * (depth - hit.z());
      depth_sum += depth - hit.z();
      angle_sum += angleDegrees(pbf_test::normalAt(out, u, v), normal);
      ++e.compared;
    }
  (void)world_to_camera;
  const double n = static_cast<double>(std::max<std::size_t>(e.compared, 1));
  e.depth_rms = std::sqrt(depth_sq / n);
  e.depth_mean = depth_sum / n;
  e.depth_spread = std::sqrt(std::max(0.0, depth_sq / n - e.depth_mean * e.depth_mean));
  e.normal_mean_deg = angle_sum / std::max<std::size_t>(e.compared, 1);
  return e;
}

class BallTest : public ::testing::Test {
 protected:
  static constexpr float kSpacing = 0.02f;
  static constexpr float kRadius = 0.5f * kSpacing;  // spheres touch, as in the node
  static constexpr float kCentreRadius = 0.15f;      // ~1800 particles
  const Eigen::Vector3f centre_{0.0f, 0.0f, 0.3f};

  pbf::RenderCamera camera() const {
    pbf::RenderCamera c;
    c.width = 320;
    c.height = 240;
    c.vertical_fov = 50.0f * static_cast<float>(M_PI) / 180.0f;
    c.camera_to_world = pbf::lookAt(Eigen::Vector3f(0.45f, -0.55f, 0.55f), centre_);
    return c;
  }

  BallErrors renderAndCompare(pbf::DepthFilter filter, const std::string& name) {
    pbf::RenderOptions options;
    options.filter = filter;
    pbf::FluidRenderer renderer(pbf::createGlBackend("osmesa"), pbf_test::shaderDir(), options);
    const auto particles = pbf_test::latticeBall(centre_, kCentreRadius, kSpacing);
    pbf::RenderOutput out;
    renderer.render(particles, kRadius, camera(), pbf_test::everything(), out);
    pbf_test::saveImages(name, out);
    // The analytic sphere is the one through the outermost particle centres (see the
    // bounds in the tests for why the fluid surface sits near it).
    const BallErrors e = compareWithSphere(camera(), out, centre_, kCentreRadius);
    std::printf("[%s] %zu particles, %zu pixels compared, %zu missing: depth RMS %.2f r "
                "(mean offset %.2f r, spread %.2f r; r = %.3f m), mean normal error %.2f deg, "
                "%.1f ms\n",
                name.c_str(), particles.size(), e.compared, e.missing, e.depth_rms / kRadius,
                e.depth_mean / kRadius, e.depth_spread / kRadius, kRadius, e.normal_mean_deg,
                out.timings.total);
    return e;
  }
};

TEST_F(BallTest, NarrowRangeDepthAndNormalsMatchTheSphere) {
  const BallErrors e = renderAndCompare(pbf::DepthFilter::NarrowRange, "ball_narrow_range");
  ASSERT_GT(e.compared, 5000u);
  EXPECT_EQ(e.missing, 0u);
  // Depth bound: RMS under half a particle radius against the sphere through the
  // outermost centres. The spheres poke out by r at the lattice sites, the treads of a
  // lattice ball's staircase boundary sit about r inside that sphere, the gaps between
  // touching spheres are closed to their neighbours' depth and a Gaussian of sigma = 2r
  // over a convex surface deepens it by ~sigma^2 / R = 0.27 r: these roughly cancel, and the
  // surface settles within a fraction of r of that sphere (measured: offset 0.2 r, RMS
  // 0.3 r). A wrong projection, a flipped axis, a filter that digs into the gaps (the
  // unfiltered spheres: RMS 1.3 r) or one that lets the background in would cost more
  // than 0.5 r. The shape itself (RMS about the mean offset) must be good to 0.35 r.
  EXPECT_LT(e.depth_rms, 0.5 * kRadius);
  EXPECT_LT(e.depth_spread, 0.35 * kRadius);
  EXPECT_LT(e.normal_mean_deg, 10.0);
}

// The bilateral option for comparison: its numbers go to the log; it must cover the ball
// and be no worse in depth than the unfiltered spheres, but its normals are not held to
// the narrow-range filter's bound (its range weights let the gaps between particles in).
TEST_F(BallTest, BilateralOptionRendersTheBall) {
  const BallErrors e = renderAndCompare(pbf::DepthFilter::Bilateral, "ball_bilateral");
  ASSERT_GT(e.compared, 5000u);
  EXPECT_EQ(e.missing, 0u);
  EXPECT_LT(e.depth_rms, 1.0 * kRadius);
}

TEST_F(BallTest, UnfilteredSpheresAreBumpierThanTheFilteredSurface) {
  const BallErrors raw = renderAndCompare(pbf::DepthFilter::None, "ball_unfiltered");
  const BallErrors smooth = renderAndCompare(pbf::DepthFilter::NarrowRange, "ball_narrow_range");
  EXPECT_GT(raw.normal_mean_deg, smooth.normal_mean_deg);
}

}  // namespace
