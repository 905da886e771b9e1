// ObstacleMover's plain parts: a request's pose (refusing what is not finite) and the bounded
// step toward a target.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "pbf_ros/ros/ObstacleMover.h"

namespace {

geometry_msgs::Pose pose(double x, double y, double z, double qx = 0, double qy = 0, double qz = 0,
                         double qw = 1) {
  geometry_msgs::Pose p;
  p.position.x = x;
  p.position.y = y;
  p.position.z = z;
  p.orientation.x = qx;
  p.orientation.y = qy;
  p.orientation.z = qz;
  p.orientation.w = qw;
  return p;
}

TEST(ObstacleMover, PosesMustBeFiniteRotations) {
  Eigen::Isometry3f t;
  std::string why;
  ASSERT_TRUE(pbf_ros::poseFromMsg(pose(0.1, 0.2, 0.3, 0, 0, 2, 2), t, why)) << why;  // normalised
  EXPECT_TRUE(t.translation().isApprox(Eigen::Vector3f(0.1f, 0.2f, 0.3f)));
  EXPECT_TRUE(t.linear().isApprox(Eigen::AngleAxisf(float(M_PI) / 2, Eigen::Vector3f::UnitZ()).toRotationMatrix(), 1e-5f));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(pbf_ros::poseFromMsg(pose(nan, 0, 0), t, why));
  EXPECT_NE(why.find("non-finite"), std::string::npos) << why;
  EXPECT_FALSE(pbf_ros::poseFromMsg(pose(0, 0, 1e300), t, why));  // finite, but not as a float
  EXPECT_NE(why.find("beyond float range"), std::string::npos) << why;  // it read "non-finite"
  EXPECT_FALSE(pbf_ros::poseFromMsg(pose(0, 0, 0, 0, 0, 0, 0), t, why));
  EXPECT_NE(why.find("zero quaternion"), std::string::npos) << why;
}

TEST(ObstacleMover, StepsTowardTheTargetByAtMostTheAllowedTravel) {
  const Eigen::Isometry3f start = Eigen::Isometry3f::Identity();
  Eigen::Isometry3f goal = Eigen::Translation3f(0.1f, 0.0f, 0.0f) *
                           Eigen::AngleAxisf(0.5f, Eigen::Vector3f::UnitZ());
  const float radius = 0.05f, max_move = 0.005f;
  Eigen::Isometry3f at = start;
  int steps = 0;
  while (!at.isApprox(goal, 1e-6f) && steps < 1000) {
    const Eigen::Isometry3f next = pbf_ros::stepToward(at, goal, max_move, radius);
    // No point within the radius travels farther than max_move in one step.
    for (const Eigen::Vector3f& p : {Eigen::Vector3f(radius, 0, 0), Eigen::Vector3f(0, -radius, 0),
                                     Eigen::Vector3f(0, 0, radius)})
      ASSERT_LE(((next * p) - (at * p)).norm(), max_move * (1.0f + 1e-4f));
    at = next;
    ++steps;
  }
  // 0.1 m + 0.5 rad x 0.05 m = 0.125 m of travel at 5 mm a step.
  EXPECT_EQ(steps, 25);
  EXPECT_TRUE(at.isApprox(goal, 1e-5f));
  // Already close enough: the whole way at once.
  const Eigen::Isometry3f near = Eigen::Translation3f(0.001f, 0.0f, 0.0f) * Eigen::Isometry3f::Identity();
  EXPECT_TRUE(pbf_ros::stepToward(start, near, max_move, radius).isApprox(near));
  // A target as far as a float goes: the obstacle still sets off, by the allowed travel
  // (the distance's square overflowed a float and it stayed put, without a word).
  for (const float far : {1e30f, 3.4e38f}) {
    const Eigen::Isometry3f distant = Eigen::Translation3f(far, 0.0f, 0.0f) * Eigen::Isometry3f::Identity();
    const Eigen::Isometry3f next = pbf_ros::stepToward(start, distant, max_move, radius);
    EXPECT_NEAR(next.translation().x(), max_move, 1e-6f) << far;
    EXPECT_TRUE(next.translation().allFinite()) << far;
  }
}

}  // namespace
