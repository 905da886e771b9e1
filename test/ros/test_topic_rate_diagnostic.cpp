// The node's clocks under a hostile ROS clock. TopicRateDiagnostic across its jumps: a /clock
// jump beyond 2^31 s made FrequencyStatus's ros::Time subtraction throw out of the diagnostics
// timer and took the node down; a jump either way now restarts the measurement. The log
// throttle measures wall time: a /clock stepping back restarted rosconsole's every period.
//
// This file sets simulated time for the whole test process (ros::Time::setNow), so it is the
// last file of test_ros_units (test/ros_tests.cmake).
#include <gtest/gtest.h>

#include <diagnostic_msgs/DiagnosticStatus.h>
#include <ros/time.h>

#include "pbf_ros/ros/TopicRateDiagnostic.h"
#include "pbf_ros/ros/WallThrottle.h"

namespace {

using diagnostic_msgs::DiagnosticStatus;

// One report at ROS time t after `messages` publications at 10 Hz over the second before.
DiagnosticStatus reportAt(pbf_ros::TopicRateDiagnostic& rate, double t, int messages) {
  for (int k = 0; k < messages; ++k) rate.tick();
  ros::Time::setNow(ros::Time(t));
  diagnostic_updater::DiagnosticStatusWrapper status;
  rate.run(status);
  return status;
}

TEST(TopicRateDiagnostic, AJumpOfTheRosClockEitherWayRestartsTheMeasurement) {
  ros::Time::init();
  ros::Time::setNow(ros::Time(100.0));
  pbf_ros::TopicRateDiagnostic rate("cloud", [] { return std::string(); });
  rate.setExpectedRate(10.0);
  EXPECT_EQ(reportAt(rate, 100.0, 0).message, "started; measuring the rate");
  double t = 100.0;
  for (int k = 0; k < 3; ++k) EXPECT_EQ(reportAt(rate, t += 1.0, 10).level, DiagnosticStatus::OK);

  // 3e9 s ahead (more than 2^31 s): no throw, measured again from there.
  DiagnosticStatus jumped;
  ASSERT_NO_THROW(jumped = reportAt(rate, 3.0e9, 10));
  EXPECT_EQ(jumped.level, DiagnosticStatus::OK);
  EXPECT_EQ(jumped.message, "the ROS clock jumped; measuring the rate again");
  t = 3.0e9;
  for (int k = 0; k < 3; ++k) EXPECT_EQ(reportAt(rate, t += 1.0, 10).level, DiagnosticStatus::OK);

  // And back: the same.
  ASSERT_NO_THROW(jumped = reportAt(rate, 50.0, 10));
  EXPECT_EQ(jumped.message, "the ROS clock jumped; measuring the rate again");
  t = 50.0;
  for (int k = 0; k < 3; ++k) EXPECT_EQ(reportAt(rate, t += 1.0, 10).level, DiagnosticStatus::OK);
  // A topic that stops while it is meant to flow is still an error, once FrequencyStatus's
  // window (5 reports) holds no message.
  DiagnosticStatus silent;
  for (int k = 0; k < 5; ++k) silent = reportAt(rate, t += 1.0, 0);
  EXPECT_EQ(silent.level, DiagnosticStatus::ERROR);
}

TEST(WallThrottle, AdmitsOncePerPeriodOfWallTimeWhateverTheRosClockDoes) {
  ros::Time::init();
  std::atomic<std::int64_t> last{std::numeric_limits<std::int64_t>::min()};
  constexpr std::int64_t kSecond = 1000000000;
  EXPECT_TRUE(pbf_ros::wallThrottleAdmits(last, 10.0, 5 * kSecond));
  for (double t : {100.0, 50.0, 1.0e9, 3.0})  {  // the ROS clock back and forth: not read
    ros::Time::setNow(ros::Time(t));
    EXPECT_FALSE(pbf_ros::wallThrottleAdmits(last, 10.0, 9 * kSecond));
  }
  EXPECT_TRUE(pbf_ros::wallThrottleAdmits(last, 10.0, 15 * kSecond));
  EXPECT_FALSE(pbf_ros::wallThrottleAdmits(last, 10.0, 24 * kSecond));
  // Its default is the steady clock: a first call is admitted, an immediate second one not.
  std::atomic<std::int64_t> fresh{std::numeric_limits<std::int64_t>::min()};
  EXPECT_TRUE(pbf_ros::wallThrottleAdmits(fresh, 60.0));
  EXPECT_FALSE(pbf_ros::wallThrottleAdmits(fresh, 60.0));
}

}  // namespace
