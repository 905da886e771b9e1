// RealTimePacer: sim time follows wall time; when behind, the debt is dropped and the
// achieved factor tells the truth.
#include <gtest/gtest.h>

#include <limits>

#include "pbf_ros/ros/RealTimePacer.h"

using pbf_ros::RealTimePacer;

TEST(RealTimePacer, StepsOnlyWhileSimTimeIsBehindTheTarget) {
  RealTimePacer pacer;
  pacer.setFactor(1.0);
  pacer.restart(100.0, 0.0);
  EXPECT_FALSE(pacer.shouldStep(100.0, 0.0));
  EXPECT_TRUE(pacer.shouldStep(100.01, 0.0));
  EXPECT_FALSE(pacer.shouldStep(100.01, 0.02));
  EXPECT_DOUBLE_EQ(pacer.wallTimeDue(0.02), 100.02);
}

TEST(RealTimePacer, FactorScalesTheTarget) {
  RealTimePacer pacer;
  pacer.setFactor(2.0);
  pacer.restart(0.0, 5.0);
  EXPECT_TRUE(pacer.shouldStep(1.0, 6.9));
  EXPECT_FALSE(pacer.shouldStep(1.0, 7.0));
  EXPECT_DOUBLE_EQ(pacer.wallTimeDue(6.0), 0.5);
}

TEST(RealTimePacer, ZeroFactorMeansAsFastAsPossible) {
  RealTimePacer pacer;
  pacer.setFactor(0.0);
  pacer.restart(0.0, 0.0);
  EXPECT_TRUE(pacer.shouldStep(0.0, 1000.0));
}

TEST(RealTimePacer, KeepingUpMeasuresTheRequestedFactor) {
  RealTimePacer pacer(0.1, 1.0);
  pacer.setFactor(0.5);
  pacer.restart(0.0, 0.0);
  double sim = 0.0;
  for (int i = 1; i <= 300; ++i) {  // 3 s of wall time, a step each 10 ms
    const double wall = 0.01 * i;
    while (pacer.shouldStep(wall, sim)) {
      sim += 0.001;
      pacer.afterStep(wall, sim);
    }
  }
  EXPECT_NEAR(pacer.achievedFactor(), 0.5, 0.02);
  EXPECT_FALSE(pacer.fallingBehind(3.0));
  EXPECT_DOUBLE_EQ(pacer.droppedSimTime(), 0.0);
}

TEST(RealTimePacer, FallingBehindDropsTheDebtAndReportsTheTruth) {
  RealTimePacer pacer(0.1, 1.0);
  pacer.setFactor(1.0);
  pacer.restart(0.0, 0.0);
  // Each step simulates 10 ms but costs 40 ms: at most 0.25x real time.
  double wall = 0.0, sim = 0.0;
  for (int i = 0; i < 200; ++i) {
    // Like the node's loop: sleep until the next step is due (at once when behind).
    if (!pacer.shouldStep(wall, sim)) wall = pacer.wallTimeDue(sim) + 1e-6;
    wall += 0.04;
    sim += 0.01;
    pacer.afterStep(wall, sim);
  }
  EXPECT_NEAR(pacer.achievedFactor(), 0.25, 0.01);
  EXPECT_TRUE(pacer.fallingBehind(wall));
  EXPECT_GT(pacer.droppedSimTime(), 5.0);
  // The debt never grows beyond max_lag: once it can keep up, it paces normally again.
  EXPECT_LE(wall - pacer.wallTimeDue(sim), 0.1 + 0.04);
}

TEST(RealTimePacer, RestartForgetsTheWindow) {
  RealTimePacer pacer;
  pacer.restart(0.0, 0.0);
  pacer.afterStep(1.0, 1.0);
  EXPECT_GT(pacer.achievedFactor(), 0.0);
  pacer.restart(2.0, 1.0);
  EXPECT_DOUBLE_EQ(pacer.achievedFactor(), 0.0);
}

TEST(RealTimePacer, BadFactorFallsBackToRealTime) {
  RealTimePacer pacer;
  pacer.setFactor(-3.0);
  EXPECT_DOUBLE_EQ(pacer.factor(), 1.0);
  pacer.setFactor(std::numeric_limits<double>::quiet_NaN());
  EXPECT_DOUBLE_EQ(pacer.factor(), 1.0);
}

TEST(RealTimePacer, SettlesAfterHalfAWindow) {
  RealTimePacer pacer(0.1, 2.0);
  pacer.restart(0.0, 0.0);
  pacer.afterStep(0.5, 0.5);
  EXPECT_FALSE(pacer.settled());
  pacer.afterStep(1.0, 1.0);
  EXPECT_TRUE(pacer.settled());
}
