// TfAttachments on a tf buffer filled here (no master): a solid attached to a frame is placed
// where tf has that frame at the step's time (interpolated), or at the latest pose on the
// wall clock (time 0); a publisher that is behind the step is waited for a bounded time.
#include <gtest/gtest.h>

#include <geometry_msgs/TransformStamped.h>

#include "pbf_ros/core/SceneSetup.h"
#include "pbf_ros/ros/TfAttachments.h"

namespace {

geometry_msgs::TransformStamped linkAt(double t, double x) {
  geometry_msgs::TransformStamped m;
  m.header.stamp = ros::Time(t);
  m.header.frame_id = "fluid_domain";
  m.child_frame_id = "link";
  m.transform.translation.x = x;
  m.transform.rotation.w = 1.0;
  return m;
}

pbf::Scene sceneWithALinkSolid() {
  pbf::Scene scene;
  scene.container = Eigen::AlignedBox3f(Eigen::Vector3f::Zero(), Eigen::Vector3f(0.4f, 0.4f, 0.4f));
  pbf::FluidBlock block;
  block.max = Eigen::Vector3f(0.4f, 0.4f, 0.1f);
  scene.fluid.push_back(block);
  scene.solver.particle_spacing = 0.05f;
  pbf::Obstacle ball;
  ball.shape = pbf::Obstacle::Shape::Sphere;
  ball.radius = 0.03f;
  ball.frame = "link";
  ball.offset = Eigen::Translation3f(0.0f, 0.0f, 0.2f) * Eigen::Quaternionf::Identity();
  scene.obstacles.push_back(ball);
  return scene;
}

TEST(TfAttachments, SolidsArePlacedAtTheStepsTimeOrTheLatestPose) {
  ros::Time::init();  // ros::Time without a node: the buffer's own clock is never read here
  auto buffer = std::make_shared<tf2_ros::Buffer>();
  ASSERT_TRUE(buffer->setTransform(linkAt(1.0, 0.1), "test"));
  ASSERT_TRUE(buffer->setTransform(linkAt(2.0, 0.3), "test"));
  const pbf::Scene scene = sceneWithALinkSolid();
  pbf::PbfSolver solver;
  pbf::setUpSolver(scene, solver);
  pbf_ros::TfAttachments tf("fluid_domain", buffer);
  auto x = [&] { return solver.obstacles()[0].pose.translation(); };

  // On /clock: the step's time, interpolated; the collision offset applied in the link frame.
  EXPECT_TRUE(tf.update(scene, solver, ros::Time(1.5), 0.02).empty());
  EXPECT_NEAR(x().x(), 0.2f, 1e-5f);
  EXPECT_NEAR(x().z(), 0.2f, 1e-6f);
  tf.update(scene, solver, ros::Time(1.25), 0.02);
  EXPECT_NEAR(x().x(), 0.15f, 1e-5f);
  // On the wall clock: the latest pose.
  tf.update(scene, solver, ros::Time(0), 0.02);
  EXPECT_NEAR(x().x(), 0.3f, 1e-5f);
  // A step ahead of the publisher: waited for (bounded, wall time), then the latest pose.
  tf.update(scene, solver, ros::Time(1.0), 0.02);
  const ros::WallTime before = ros::WallTime::now();
  tf.update(scene, solver, ros::Time(2.5), 0.05);
  EXPECT_GE((ros::WallTime::now() - before).toSec(), 0.045);
  EXPECT_NEAR(x().x(), 0.3f, 1e-5f);

  // A frame tf does not know: the solid stays, and its name is reported after the grace.
  pbf::Scene lost = scene;
  lost.obstacles[0].frame = "nowhere";
  EXPECT_TRUE(tf.update(lost, solver, ros::Time(1.5), 0.0).empty());  // within the grace
  EXPECT_NEAR(x().x(), 0.3f, 1e-5f);
  Eigen::Isometry3f pose;
  EXPECT_FALSE(tf.currentPose("nowhere", pose));
  ASSERT_TRUE(tf.currentPose("link", pose));
  EXPECT_NEAR(pose.translation().x(), 0.3f, 1e-5f);
}

}  // namespace
