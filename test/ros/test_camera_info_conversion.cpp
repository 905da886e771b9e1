// CameraInfo and the camera transform agree with the renderer's camera: a point projected
// with the published K / P (after the published transform) lands on the renderer's pixel.
// And the surface images have the layout sensor_msgs expects.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include <Eigen/Geometry>
#include <sensor_msgs/image_encodings.h>

#include "pbf_ros/ros/CameraInfoConversion.h"
#include "pbf_ros/ros/SurfaceImageConversion.h"

namespace {

pbf::RenderCamera someCamera() {
  pbf::RenderCamera camera;
  camera.width = 160;
  camera.height = 120;
  camera.vertical_fov = 0.9f;
  camera.camera_to_world =
      pbf::lookAt(Eigen::Vector3f(2.0f, -1.5f, 1.2f), Eigen::Vector3f(0.8f, 0.25f, 0.3f));
  return camera;
}

std_msgs::Header someHeader() {
  std_msgs::Header header;
  header.stamp = ros::Time(12, 345);
  header.frame_id = "fluid_camera_optical";
  return header;
}

}  // namespace

TEST(CameraInfoConversion, KAndPAreTheRenderersIntrinsics) {
  const pbf::RenderCamera camera = someCamera();
  const sensor_msgs::CameraInfo info = pbf_ros::toCameraInfo(camera, someHeader());
  const pbf::PinholeIntrinsics k = pbf::intrinsicsOf(camera);
  EXPECT_EQ(info.header.frame_id, "fluid_camera_optical");
  EXPECT_EQ(info.header.stamp, ros::Time(12, 345));
  EXPECT_EQ(info.width, 160u);
  EXPECT_EQ(info.height, 120u);
  EXPECT_DOUBLE_EQ(info.K[0], k.fx);
  EXPECT_DOUBLE_EQ(info.K[2], k.cx);
  EXPECT_DOUBLE_EQ(info.K[4], k.fy);
  EXPECT_DOUBLE_EQ(info.K[5], k.cy);
  EXPECT_DOUBLE_EQ(info.K[8], 1.0);
  EXPECT_DOUBLE_EQ(info.K[1], 0.0);
  EXPECT_DOUBLE_EQ(info.P[0], k.fx);
  EXPECT_DOUBLE_EQ(info.P[2], k.cx);
  EXPECT_DOUBLE_EQ(info.P[3], 0.0);
  EXPECT_DOUBLE_EQ(info.P[5], k.fy);
  EXPECT_DOUBLE_EQ(info.P[6], k.cy);
  EXPECT_DOUBLE_EQ(info.P[10], 1.0);
  EXPECT_DOUBLE_EQ(info.R[0] * info.R[4] * info.R[8], 1.0);
  EXPECT_EQ(info.distortion_model, "plumb_bob");
  ASSERT_EQ(info.D.size(), 5u);
  for (double d : info.D) EXPECT_EQ(d, 0.0);
  // Principal point at the image centre: (w - 1) / 2, (h - 1) / 2.
  EXPECT_DOUBLE_EQ(info.K[2], 79.5);
  EXPECT_DOUBLE_EQ(info.K[5], 59.5);
}

TEST(CameraInfoConversion, TransformAndKProjectLikeTheRenderer) {
  const pbf::RenderCamera camera = someCamera();
  const sensor_msgs::CameraInfo info = pbf_ros::toCameraInfo(camera, someHeader());
  const geometry_msgs::TransformStamped t =
      pbf_ros::toCameraTransform(camera, "fluid_domain", "fluid_camera_optical", ros::Time(3));
  EXPECT_EQ(t.header.frame_id, "fluid_domain");
  EXPECT_EQ(t.child_frame_id, "fluid_camera_optical");
  const Eigen::Quaterniond q(t.transform.rotation.w, t.transform.rotation.x,
                             t.transform.rotation.y, t.transform.rotation.z);
  EXPECT_NEAR(q.norm(), 1.0, 1e-6);
  const Eigen::Vector3d origin(t.transform.translation.x, t.transform.translation.y,
                               t.transform.translation.z);
  for (const Eigen::Vector3f& world : {Eigen::Vector3f(0.8f, 0.25f, 0.3f),
                                      Eigen::Vector3f(1.5f, 0.4f, 0.1f),
                                      Eigen::Vector3f(0.1f, 0.0f, 0.7f)}) {
    // What a ROS user does: fluid_domain point -> optical frame through tf, then P.
    const Eigen::Vector3d p = q.inverse() * (world.cast<double>() - origin);
    const double u = (info.P[0] * p.x() + info.P[2] * p.z()) / p.z();
    const double v = (info.P[5] * p.y() + info.P[6] * p.z()) / p.z();
    Eigen::Vector2f pixel;
    float depth = 0.0f;
    ASSERT_TRUE(pbf::projectToPixel(camera, world, pixel, depth));
    EXPECT_NEAR(u, pixel.x(), 1e-3);
    EXPECT_NEAR(v, pixel.y(), 1e-3);
    EXPECT_NEAR(p.z(), depth, 1e-5);
  }
}

TEST(SurfaceImageConversion, ColourIsRgb8AndDepthIs32FC1WithNaNForNoFluid) {
  pbf::RenderOutput out;
  out.width = 3;
  out.height = 2;
  for (int i = 0; i < 6; ++i) {
    out.rgba.insert(out.rgba.end(), {static_cast<std::uint8_t>(i), 10, 20, 255});
    out.depth.push_back(i == 4 ? std::numeric_limits<float>::quiet_NaN() : 0.5f + i);
  }
  sensor_msgs::Image colour, depth;
  ASSERT_TRUE(pbf_ros::toColorImage(out, someHeader(), colour));
  ASSERT_TRUE(pbf_ros::toDepthImage(out, someHeader(), depth));
  EXPECT_EQ(colour.encoding, sensor_msgs::image_encodings::RGB8);
  EXPECT_EQ(colour.width, 3u);
  EXPECT_EQ(colour.height, 2u);
  EXPECT_EQ(colour.step, 9u);
  EXPECT_EQ(colour.data.size(), 18u);
  EXPECT_EQ(colour.data[3 * 5], 5);       // last pixel, red
  EXPECT_EQ(colour.data[3 * 5 + 1], 10);  // green
  EXPECT_EQ(colour.data[3 * 5 + 2], 20);  // blue; the alpha is dropped
  EXPECT_EQ(depth.encoding, sensor_msgs::image_encodings::TYPE_32FC1);
  EXPECT_EQ(depth.step, 12u);
  ASSERT_EQ(depth.data.size(), 24u);
  float values[6];
  std::memcpy(values, depth.data.data(), sizeof(values));
  EXPECT_FLOAT_EQ(values[0], 0.5f);
  EXPECT_FLOAT_EQ(values[5], 5.5f);
  EXPECT_TRUE(std::isnan(values[4]));
  EXPECT_EQ(colour.header.frame_id, depth.header.frame_id);
  EXPECT_EQ(colour.header.stamp, depth.header.stamp);
}

TEST(SurfaceImageConversion, WhatWasNotRenderedIsNotConverted) {
  pbf::RenderOutput out;
  out.width = 4;
  out.height = 4;
  sensor_msgs::Image image;
  EXPECT_FALSE(pbf_ros::toColorImage(out, someHeader(), image));
  EXPECT_FALSE(pbf_ros::toDepthImage(out, someHeader(), image));
}
