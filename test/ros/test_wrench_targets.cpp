// ~wrench/<name>: which topics a scene gets, and a solver wrench expressed in a solid's frame.
#include <gtest/gtest.h>

#include "pbf_ros/ros/SolidWrenchTargets.h"
#include "pbf_ros/ros/StatsConversion.h"

namespace {

pbf::Obstacle ball(const std::string& frame = "") {
  pbf::Obstacle o;
  o.shape = pbf::Obstacle::Shape::Sphere;
  o.radius = 0.05f;
  o.frame = frame;
  return o;
}

TEST(WrenchTargets, ContainerSceneObstaclesAndRobotLinks) {
  pbf::Scene scene;
  scene.container_frame = "tank";
  scene.obstacles = {ball(), ball("cup_frame"), ball("arm/link-1"), ball("arm/link-1"), ball("container")};
  std::vector<pbf_ros::RobotLinkSolids> links(2);
  links[0].link = "arm/link-1";
  links[0].obstacles = {2, 3};
  links[1].link = "container";  // a link may be named like another topic
  links[1].obstacles = {4};
  const auto t = pbf_ros::wrenchTargets(scene, links, "fluid_domain");
  ASSERT_EQ(t.size(), 5u);
  EXPECT_EQ(t[0].name, "container");
  EXPECT_TRUE(t[0].container);
  EXPECT_EQ(t[0].frame, "tank");
  EXPECT_EQ(t[1].name, "obstacle_0");
  EXPECT_EQ(t[1].frame, "fluid_domain");  // a static obstacle has no frame of its own
  EXPECT_EQ(t[2].name, "obstacle_1");
  EXPECT_EQ(t[2].frame, "cup_frame");
  EXPECT_EQ(t[3].name, "arm_link_1");
  EXPECT_EQ(t[3].frame, "arm/link-1");
  EXPECT_EQ(t[3].obstacles, (std::vector<std::size_t>{2, 3}));
  EXPECT_EQ(t[4].name, "container_2");
  EXPECT_EQ(pbf_ros::topicSafeName("2nd link"), "s_2nd_link");
}

TEST(WrenchTargets, WrenchIsExpressedInTheSolidsFrameAboutItsOrigin) {
  // A link frame at (1, 0, -0.5), turned 90 deg about z; its solid's centre (collision
  // origin) 0.5 m above the frame origin. The fluid pushes the solid along +x with 10 N.
  pbf::Obstacle o = ball("link");
  o.offset = Eigen::Isometry3f(Eigen::Translation3f(0.0f, 0.0f, 0.5f));
  const Eigen::Isometry3f link = Eigen::Translation3f(1.0f, 0.0f, -0.5f) *
                                 Eigen::AngleAxisf(float(M_PI / 2), Eigen::Vector3f::UnitZ());
  o.pose = link * o.offset;
  pbf::Scene scene;
  scene.obstacles = {o};
  std::vector<pbf_ros::RobotLinkSolids> links(1);
  links[0].link = "link";
  links[0].obstacles = {0};
  const auto targets = pbf_ros::wrenchTargets(scene, links, "fluid_domain");
  ASSERT_EQ(targets.size(), 2u);
  pbf::SolidWrenches w;
  w.valid = true;
  w.obstacles.resize(1);
  w.obstacles[0].force = Eigen::Vector3d(10, 0, 0);  // torque about the solid's centre: 0
  const Eigen::Isometry3d frame =
      pbf_ros::targetFramePose(targets[1], scene, Eigen::Isometry3f::Identity(), scene.obstacles);
  EXPECT_TRUE(frame.isApprox(link.cast<double>(), 1e-6));
  const pbf::Wrench local = pbf_ros::targetWrench(targets[1], w, Eigen::Isometry3f::Identity(),
                                                  scene.obstacles, frame);
  // Domain +x is the frame's -y; the 0.5 m lever along z gives 5 N m about domain +y,
  // which is the frame's +x.
  EXPECT_NEAR((local.force - Eigen::Vector3d(0, -10, 0)).norm(), 0.0, 1e-5);
  EXPECT_NEAR((local.torque - Eigen::Vector3d(5, 0, 0)).norm(), 0.0, 1e-5);
  // All solids together in fluid_domain about its origin: lever (1, 0, 0) x (10, 0, 0) = 0.
  const pbf::Wrench total = pbf_ros::totalWrench(w, Eigen::Isometry3f::Identity(), scene.obstacles);
  EXPECT_NEAR((total.force - Eigen::Vector3d(10, 0, 0)).norm(), 0.0, 1e-9);
  EXPECT_NEAR(total.torque.norm(), 0.0, 1e-6);
}

TEST(WrenchTargets, StatsCarryTheSumOnlyWhenMeasuredAndFinite) {
  pbf_ros::StatsContext c;
  c.wrench_tracked = true;
  c.solids_wrench.force = Eigen::Vector3d(0, 0, -200);
  auto m = pbf_ros::toStatsMessage(pbf::StepStats(), c);
  EXPECT_TRUE(m.wrench_tracked);
  EXPECT_DOUBLE_EQ(m.solids_wrench.force.z, -200.0);
  c.solids_wrench.torque.x() = std::nan("");
  m = pbf_ros::toStatsMessage(pbf::StepStats(), c);
  EXPECT_FALSE(m.wrench_tracked);
  EXPECT_DOUBLE_EQ(m.solids_wrench.force.z, 0.0);
  EXPECT_DOUBLE_EQ(m.solids_wrench.torque.x, 0.0);
}

}  // namespace
