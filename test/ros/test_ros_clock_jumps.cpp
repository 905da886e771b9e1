// RosClockJumps: ROS time going back, or leaping far ahead of the wall clock, is a jump; a
// clock that runs faster or slower than the wall, or stands still, is not.

#include <gtest/gtest.h>

#include "pbf_ros/ros/RosClockJumps.h"

TEST(RosClockJumps, BackOrFarAheadIsAJumpFastOrStoppedIsNot) {
  pbf_ros::RosClockJumps jumps;
  EXPECT_EQ(jumps.update(1000.0, 5.0), 0.0);  // the first sample only starts the watch
  EXPECT_EQ(jumps.update(1000.1, 5.1), 0.0);  // with the wall
  EXPECT_EQ(jumps.update(1000.6, 5.2), 0.0);  // a simulator at 5x real time
  EXPECT_EQ(jumps.update(1000.6, 6.2), 0.0);  // a paused simulator
  EXPECT_NEAR(jumps.update(500.0, 6.3), -500.7, 1e-9);  // a bag that looped
  EXPECT_EQ(jumps.update(500.1, 6.4), 0.0);
  EXPECT_NEAR(jumps.update(1e9, 6.5), 1e9 - 500.2, 1e-3);  // far ahead
}

TEST(RosClockJumps, ALeapIsMeasuredAgainstTheWallTimeElapsed) {
  pbf_ros::RosClockJumps jumps;
  jumps.update(0.0, 0.0);
  EXPECT_EQ(jumps.update(30.0, 3.0), 0.0);  // 10x over 3 s: at the bound, not beyond it
  EXPECT_EQ(jumps.update(31.0, 3.0), 0.0);  // 1 s at once: kMinLeap
  EXPECT_NEAR(jumps.update(32.5, 3.0), 1.5, 1e-9);
}
