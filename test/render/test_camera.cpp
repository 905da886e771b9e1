// The published pinhole model must agree with what the GL pipeline draws: a point
// projected with K lands on the pixel where it appears, rows run top-down, and the depth
// image holds metres along the optical axis.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "RenderTestSupport.h"

namespace {

pbf::RenderCamera levelCamera() {
  pbf::RenderCamera camera;
  camera.width = 320;
  camera.height = 240;
  camera.vertical_fov = 60.0f * static_cast<float>(M_PI) / 180.0f;
  // At z = 0.5 looking along world +x: image right is world -y, image down is world -z.
  camera.camera_to_world =
      pbf::lookAt(Eigen::Vector3f(0.0f, 0.0f, 0.5f), Eigen::Vector3f(1.0f, 0.0f, 0.5f));
  return camera;
}

TEST(RenderCamera, IntrinsicsFollowFromFieldOfViewAndSize) {
  const pbf::RenderCamera camera = levelCamera();
  const pbf::PinholeIntrinsics k = pbf::intrinsicsOf(camera);
  const double f = 120.0 / std::tan(30.0 * M_PI / 180.0);
  EXPECT_NEAR(k.fx, f, 1e-3);
  EXPECT_NEAR(k.fy, f, 1e-3);
  EXPECT_DOUBLE_EQ(k.cx, 159.5);
  EXPECT_DOUBLE_EQ(k.cy, 119.5);
}

TEST(RenderCamera, LookAtGivesTheOpticalConvention) {
  const Eigen::Matrix3f r = levelCamera().camera_to_world.linear();
  EXPECT_TRUE(r.col(2).isApprox(Eigen::Vector3f::UnitX()));     // z forward
  EXPECT_TRUE(r.col(0).isApprox(-Eigen::Vector3f::UnitY()));    // x right
  EXPECT_TRUE(r.col(1).isApprox(-Eigen::Vector3f::UnitZ()));    // y down
}

// The GL matrices and the pinhole model are the same projection, to a thousandth of a pixel.
TEST(RenderCamera, GlProjectionAgreesWithIntrinsics) {
  pbf::RenderCamera camera = levelCamera();
  camera.camera_to_world = pbf::lookAt(Eigen::Vector3f(0.3f, -0.4f, 0.9f),
                                       Eigen::Vector3f(1.2f, 0.5f, 0.1f));
  const Eigen::Matrix4f clip_from_world = pbf::glProjection(camera) * pbf::glViewFromWorld(camera);
  for (const Eigen::Vector3f& point : {Eigen::Vector3f(1.3f, 0.4f, 0.2f),
                                      Eigen::Vector3f(1.0f, 0.8f, 0.5f),
                                      Eigen::Vector3f(1.6f, 0.2f, 0.0f)}) {
    const Eigen::Vector4f clip = clip_from_world * point.homogeneous();
    const Eigen::Vector2f ndc = clip.head<2>() / clip.w();
    // Window coordinates (origin bottom-left, pixel centres at +0.5) to pixel-centre
    // coordinates with rows from the top.
    const float u = 0.5f * (ndc.x() + 1.0f) * camera.width - 0.5f;
    const float v = camera.height - 0.5f * (ndc.y() + 1.0f) * camera.height - 0.5f;
    Eigen::Vector2f pixel;
    float depth = 0;
    ASSERT_TRUE(pbf::projectToPixel(camera, point, pixel, depth));
    EXPECT_NEAR(pixel.x(), u, 1e-3);
    EXPECT_NEAR(pixel.y(), v, 1e-3);
    EXPECT_NEAR(depth, clip.w(), 1e-5);  // GL's w is the distance along the optical axis
  }
}

struct Blob {
  double u = 0, v = 0;  // centroid of the pixels with fluid
  int pixels = 0;
  float nearest = std::numeric_limits<float>::infinity();
};

Blob findBlob(const pbf::RenderOutput& out) {
  Blob blob;
  for (int v = 0; v < out.height; ++v)
    for (int u = 0; u < out.width; ++u) {
      const float d = out.depth[static_cast<std::size_t>(v) * out.width + u];
      if (!std::isfinite(d)) continue;
      blob.u += u;
      blob.v += v;
      ++blob.pixels;
      blob.nearest = std::min(blob.nearest, d);
    }
  if (blob.pixels) blob.u /= blob.pixels, blob.v /= blob.pixels;
  return blob;
}

// One small sphere, away from the image centre, up and to the left: it must appear where
// K puts its centre (the perspective silhouette of a sphere this small, r/d = 1.5 %, is
// centred on the projected centre to ~0.02 pixel; the pixel centroid adds ~0.1), in the top-left quadrant (rows top-down, x to
// the right), and its nearest depth must be its distance along the axis minus its radius.
TEST(RenderCamera, PointProjectedWithIntrinsicsLandsWhereItAppears) {
  const pbf::RenderCamera camera = levelCamera();
  pbf::RenderOptions options;
  options.filter = pbf::DepthFilter::None;  // the raw sphere, nothing moved
  pbf::FluidRenderer renderer(pbf::createGlBackend("osmesa"), pbf_test::shaderDir(), options);
  const Eigen::Vector3f point(2.0f, 0.45f, 0.85f);  // ahead, to the left (+y), above
  const float radius = 0.03f;
  pbf::RenderOutput out;
  pbf::RenderRequest request;
  request.image = true;
  request.depth = true;
  renderer.render({point}, radius, camera, request, out);
  pbf_test::saveImages("camera_point", out);

  Eigen::Vector2f expected;
  float axis_depth = 0;
  ASSERT_TRUE(pbf::projectToPixel(camera, point, expected, axis_depth));
  const Blob blob = findBlob(out);
  std::printf("projected (%.2f, %.2f), rendered centroid (%.2f, %.2f) of %d pixels, "
              "nearest depth %.4f m (centre at %.4f m along the axis)\n",
              expected.x(), expected.y(), blob.u, blob.v, blob.pixels, blob.nearest,
              axis_depth);
  ASSERT_GT(blob.pixels, 20);
  EXPECT_LT(expected.x(), 0.5f * camera.width);   // left of centre
  EXPECT_LT(expected.y(), 0.5f * camera.height);  // above centre: rows are top-down
  EXPECT_NEAR(blob.u, expected.x(), 0.25);
  EXPECT_NEAR(blob.v, expected.y(), 0.25);
  // The nearest point of the sphere lies on the ray to its centre, at distance
  // |c| - r; its depth along the axis is that times cos(angle off axis).
  const Eigen::Vector3f centre_camera = camera.camera_to_world.inverse() * point;
  const float nearest_depth =
      (centre_camera.norm() - radius) * centre_camera.z() / centre_camera.norm();
  EXPECT_NEAR(blob.nearest, nearest_depth, 2e-3f);
}

}  // namespace
