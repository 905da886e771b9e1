// TfAttachments on a tf buffer filled here (no master): a solid attached to a frame is placed
// where tf has that frame at the step's time (interpolated), or at the latest pose on the
// wall clock (time 0); a publisher that is behind the step is waited for a bounded time, but
// only when its next pose is due, once per frame, and not again after a wait in vain.
#include <gtest/gtest.h>

#include <geometry_msgs/TransformStamped.h>

#include <limits>

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
  EXPECT_TRUE(tf.update(scene, solver, ros::Time(1.5), 0.02).missing.empty());
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
  EXPECT_TRUE(tf.update(lost, solver, ros::Time(1.5), 0.0).missing.empty());  // within the grace
  EXPECT_NEAR(x().x(), 0.3f, 1e-5f);
  Eigen::Isometry3f pose;
  EXPECT_FALSE(tf.currentPose("nowhere", pose));
  ASSERT_TRUE(tf.currentPose("link", pose));
  EXPECT_NEAR(pose.translation().x(), 0.3f, 1e-5f);
}


// Seconds of wall time one update takes.
template <typename Update>
double wallSecondsOf(Update update) {
  const ros::WallTime before = ros::WallTime::now();
  update();
  return (ros::WallTime::now() - before).toSec();
}

// A publisher on the node's /clock sends its next pose only once the simulation reaches it:
// between two of its poses the steps take the latest without waiting (a pouring cup at 60 Hz
// made every step between its poses wait, real-time factor 0.05). When its next pose is due,
// the step waits once per frame, however many solids the frame carries, and a publisher that
// did not come is not waited for again until it sends a newer pose.
TEST(TfAttachments, WaitsOnlyForAPoseThatIsDueAndOncePerFrame) {
  ros::Time::init();
  auto buffer = std::make_shared<tf2_ros::Buffer>();
  ASSERT_TRUE(buffer->setTransform(linkAt(1.0, 0.1), "test"));
  pbf::Scene scene = sceneWithALinkSolid();
  for (int k = 0; k < 4; ++k) scene.obstacles.push_back(scene.obstacles.front());  // five on "link"
  pbf::PbfSolver solver;
  pbf::setUpSolver(scene, solver);
  pbf_ros::TfAttachments tf("fluid_domain", buffer);
  constexpr double kWait = 0.2;  // [wall s] per wait: five waits would take 1 s

  // Its interval not known yet: due, waited for once for the five solids, in vain.
  pbf_ros::TfAttachments::Report report;
  const double first = wallSecondsOf([&] { report = tf.update(scene, solver, ros::Time(1.5), kWait); });
  EXPECT_GE(first, 0.9 * kWait);
  EXPECT_LT(first, 3.0 * kWait);
  ASSERT_EQ(report.behind.size(), 1u);
  EXPECT_EQ(report.behind[0].first, "link");
  EXPECT_NEAR(report.behind[0].second, 0.5, 1e-9);
  // Waited for in vain since its latest pose: not again, and still reported behind.
  EXPECT_LT(wallSecondsOf([&] { report = tf.update(scene, solver, ros::Time(1.6), kWait); }), 0.5 * kWait);
  ASSERT_EQ(report.behind.size(), 1u);
  EXPECT_NEAR(report.behind[0].second, 0.6, 1e-9);

  // A newer pose: its interval is 1 s, so at 2.5 s the next is not due yet (no wait, not
  // behind), at 3.1 s it is (a wait), and overdue by less than 0.25 s (not behind: jitter),
  // at 3.5 s by more (behind).
  ASSERT_TRUE(buffer->setTransform(linkAt(2.0, 0.3), "test"));
  EXPECT_LT(wallSecondsOf([&] { report = tf.update(scene, solver, ros::Time(2.5), kWait); }), 0.5 * kWait);
  EXPECT_TRUE(report.behind.empty());
  EXPECT_NEAR(solver.obstacles()[4].pose.translation().x(), 0.3f, 1e-5f);  // the latest pose
  EXPECT_GE(wallSecondsOf([&] { report = tf.update(scene, solver, ros::Time(3.1), kWait); }), 0.9 * kWait);
  EXPECT_TRUE(report.behind.empty());
  report = tf.update(scene, solver, ros::Time(3.5), kWait);
  ASSERT_EQ(report.behind.size(), 1u);
  EXPECT_NEAR(report.behind[0].second, 1.5, 1e-9);

  // A pose tf holds but that is not finite (tf2 takes infinities): named, the solid stays.
  geometry_msgs::TransformStamped far = linkAt(4.0, std::numeric_limits<double>::infinity());
  ASSERT_TRUE(buffer->setTransform(far, "test"));
  report = tf.update(scene, solver, ros::Time(0), kWait);
  ASSERT_EQ(report.non_finite.size(), 1u);
  EXPECT_EQ(report.non_finite[0], "link");
  EXPECT_TRUE(report.missing.empty());
  EXPECT_NEAR(solver.obstacles()[0].pose.translation().x(), 0.3f, 1e-5f);
}

}  // namespace
