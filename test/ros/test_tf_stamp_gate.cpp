// TfStampGate: a floating body's pose goes out on tf once per stamp (a reset while paused on
// /clock comes at the stamp of the last step, which tf2 listeners refuse as TF_REPEATED_DATA).
#include <gtest/gtest.h>

#include "pbf_ros/ros/TfStampGate.h"

namespace {

TEST(TfStampGate, AStampIsSentOncePerFrame) {
  pbf_ros::TfStampGate gate;
  const ros::Time t(7.5), later(7.504);
  EXPECT_TRUE(gate.admit("ball", t));
  EXPECT_FALSE(gate.admit("ball", t));   // a rebuild while paused: same simulated time
  EXPECT_FALSE(gate.admit("ball", t));   // and again
  EXPECT_TRUE(gate.admit("raft", t));    // another frame has its own stamps
  EXPECT_TRUE(gate.admit("ball", later));  // the next step
  EXPECT_FALSE(gate.admit("ball", later));
  // The wall clock's stamps may restart lower (resume after a fast run): not a repeat.
  EXPECT_TRUE(gate.admit("ball", t));
}

TEST(TfStampGate, TheFirstStampMayBeZero) {
  pbf_ros::TfStampGate gate;  // on /clock the start-up state is stamped 0
  EXPECT_TRUE(gate.admit("ball", ros::Time(0)));
  EXPECT_FALSE(gate.admit("ball", ros::Time(0)));
}

}  // namespace
