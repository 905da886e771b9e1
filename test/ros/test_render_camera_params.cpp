// Fluid.cfg render parameters -> camera and options: the automatic camera frames the whole
// container, an explicit camera looks where it is told, user camera settings switch the
// automatic camera off.
#include <gtest/gtest.h>

#include <cmath>

#include "pbf_ros/ros/RenderCameraParams.h"

namespace {

const Eigen::AlignedBox3f kDamBreak(Eigen::Vector3f(0.0f, 0.0f, 0.0f),
                                    Eigen::Vector3f(1.6f, 0.5f, 0.8f));

Eigen::Vector3f corner(const Eigen::AlignedBox3f& box, int i) {
  return Eigen::Vector3f((i & 1) ? box.max().x() : box.min().x(),
                         (i & 2) ? box.max().y() : box.min().y(),
                         (i & 4) ? box.max().z() : box.min().z());
}

}  // namespace

TEST(RenderCameraParams, DefaultsAre640x480At60DegreesNarrowRangeAt10Hz) {
  const pbf_ros::FluidConfig config = pbf_ros::FluidConfig::__getDefault__();
  const pbf_ros::SurfaceSettings s = pbf_ros::surfaceSettingsFromConfig(config, kDamBreak);
  EXPECT_EQ(s.camera.width, 640);
  EXPECT_EQ(s.camera.height, 480);
  EXPECT_NEAR(s.camera.vertical_fov, M_PI / 3.0, 1e-6);
  EXPECT_EQ(s.options.filter, pbf::DepthFilter::NarrowRange);
  EXPECT_DOUBLE_EQ(s.rate, 10.0);
  EXPECT_TRUE(config.camera_auto);
}

TEST(RenderCameraParams, AutomaticCameraSeesEveryCornerOfTheContainer) {
  for (const Eigen::AlignedBox3f& box :
       {kDamBreak, Eigen::AlignedBox3f(Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(0.4f, 0.4f, 0.6f)),
        Eigen::AlignedBox3f(Eigen::Vector3f(-1, 2, 0), Eigen::Vector3f(3.0f, 2.5f, 0.3f))}) {
    for (const auto& size : {std::make_pair(640, 480), std::make_pair(160, 120),
                             std::make_pair(200, 400)}) {
      pbf_ros::FluidConfig config = pbf_ros::FluidConfig::__getDefault__();
      config.render_width = size.first;
      config.render_height = size.second;
      const pbf::RenderCamera camera = pbf_ros::renderCameraFromConfig(config, box);
      float max_u_fraction = 0.0f, max_v_fraction = 0.0f;
      for (int i = 0; i < 8; ++i) {
        Eigen::Vector2f pixel;
        float depth = 0.0f;
        ASSERT_TRUE(pbf::projectToPixel(camera, corner(box, i), pixel, depth));
        EXPECT_GT(depth, camera.near_clip);
        EXPECT_LT(depth, camera.far_clip);
        EXPECT_GE(pixel.x(), -0.5f);
        EXPECT_LE(pixel.x(), camera.width - 0.5f);
        EXPECT_GE(pixel.y(), -0.5f);
        EXPECT_LE(pixel.y(), camera.height - 0.5f);
        max_u_fraction = std::max(max_u_fraction, std::abs(pixel.x() - 0.5f * camera.width) /
                                                      (0.5f * camera.width));
        max_v_fraction = std::max(max_v_fraction, std::abs(pixel.y() - 0.5f * camera.height) /
                                                      (0.5f * camera.height));
      }
      // ... and is not needlessly far: the container fills one of the image's extents.
      EXPECT_GT(std::max(max_u_fraction, max_v_fraction), 0.85f);
      // Looking at the centre, image up = +z (world z projects upwards on the image).
      Eigen::Vector2f centre, above;
      float d = 0.0f;
      ASSERT_TRUE(pbf::projectToPixel(camera, box.center(), centre, d));
      EXPECT_NEAR(centre.x(), 0.5f * camera.width - 0.5f, 1e-2f);
      EXPECT_NEAR(centre.y(), 0.5f * camera.height - 0.5f, 1e-2f);
      ASSERT_TRUE(pbf::projectToPixel(camera, box.center() + Eigen::Vector3f(0, 0, 0.01f), above, d));
      EXPECT_LT(above.y(), centre.y());
      // From above: the camera is higher than the container's centre.
      EXPECT_GT(camera.camera_to_world.translation().z(), box.center().z());
    }
  }
}

TEST(RenderCameraParams, ExplicitCameraLooksAtItsTargetInTheOpticalConvention) {
  pbf_ros::FluidConfig config = pbf_ros::FluidConfig::__getDefault__();
  config.camera_auto = false;
  config.camera_position_x = 3.0;
  config.camera_position_y = 0.25;
  config.camera_position_z = 0.4;
  config.camera_look_at_x = 0.0;
  config.camera_look_at_y = 0.25;
  config.camera_look_at_z = 0.4;
  config.render_vfov = 0.5;
  const pbf::RenderCamera camera = pbf_ros::renderCameraFromConfig(config, kDamBreak);
  EXPECT_TRUE(camera.camera_to_world.translation().isApprox(Eigen::Vector3f(3.0f, 0.25f, 0.4f)));
  const Eigen::Matrix3f r = camera.camera_to_world.linear();
  EXPECT_TRUE(r.col(2).isApprox(-Eigen::Vector3f::UnitX()));  // z forward (towards -x)
  EXPECT_TRUE(r.col(1).isApprox(-Eigen::Vector3f::UnitZ()));  // y down
  EXPECT_TRUE(r.col(0).isApprox(Eigen::Vector3f::UnitY()));   // x right
  EXPECT_FLOAT_EQ(camera.vertical_fov, 0.5f);
}

TEST(RenderCameraParams, EyeAtTheTargetDoesNotMakeNaNs) {
  pbf_ros::FluidConfig config = pbf_ros::FluidConfig::__getDefault__();
  config.camera_auto = false;
  config.camera_position_x = config.camera_look_at_x = 1.0;
  config.camera_position_y = config.camera_look_at_y = 1.0;
  config.camera_position_z = config.camera_look_at_z = 1.0;
  const pbf::RenderCamera camera = pbf_ros::renderCameraFromConfig(config, kDamBreak);
  EXPECT_TRUE(camera.camera_to_world.matrix().allFinite());
}

TEST(RenderCameraParams, FilterAndItsParametersReachTheOptions) {
  pbf_ros::FluidConfig config = pbf_ros::FluidConfig::__getDefault__();
  config.render_filter = "bilateral";
  config.render_filter_sigma = 2.5;
  config.render_filter_max_radius = 9;
  config.render_gap_closing = 0.0;
  config.render_bilateral_depth_sigma = 3.0;
  config.render_narrow_range_threshold = 5.0;
  config.render_narrow_range_clamp = 0.5;
  config.render_surface_only = false;
  config.render_background = false;
  const Eigen::AlignedBox3f raised(Eigen::Vector3f(0, 0, 0.3f), Eigen::Vector3f(1, 1, 1));
  const pbf::RenderOptions o = pbf_ros::renderOptionsFromConfig(config, raised);
  EXPECT_EQ(o.filter, pbf::DepthFilter::Bilateral);
  EXPECT_FLOAT_EQ(o.filter_sigma_in_radii, 2.5f);
  EXPECT_EQ(o.max_filter_radius_pixels, 9);
  EXPECT_FLOAT_EQ(o.gap_closing_in_radii, 0.0f);
  EXPECT_FLOAT_EQ(o.bilateral_depth_sigma_in_radii, 3.0f);
  EXPECT_FLOAT_EQ(o.narrow_range_threshold_in_radii, 5.0f);
  EXPECT_FLOAT_EQ(o.narrow_range_clamp_in_radii, 0.5f);
  EXPECT_FALSE(o.surface_particles_only);
  EXPECT_FALSE(o.draw_background);
  EXPECT_FLOAT_EQ(o.floor_height, 0.3f);  // the container's bottom

  config.render_filter = "none";
  EXPECT_EQ(pbf_ros::renderOptionsFromConfig(config, raised).filter, pbf::DepthFilter::None);
  config.render_filter = "gaussian";
  std::vector<std::string> notes;
  EXPECT_EQ(pbf_ros::renderOptionsFromConfig(config, raised, &notes).filter,
            pbf::DepthFilter::NarrowRange);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("render_filter"), std::string::npos);
}

TEST(RenderCameraParams, SettingACameraPositionTurnsTheAutomaticCameraOff) {
  pbf_ros::FluidConfig config = pbf_ros::FluidConfig::__getDefault__();
  EXPECT_FALSE(pbf_ros::applyCameraOverride({"render_rate", "xsph_viscosity"}, config));
  EXPECT_TRUE(config.camera_auto);
  EXPECT_TRUE(pbf_ros::applyCameraOverride({"camera_look_at_z"}, config));
  EXPECT_FALSE(config.camera_auto);
  // ... unless the same request says what camera_auto should be.
  config.camera_auto = true;
  EXPECT_FALSE(pbf_ros::applyCameraOverride({"camera_position_x", "camera_auto"}, config));
  EXPECT_TRUE(config.camera_auto);
}
