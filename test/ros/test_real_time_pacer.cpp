// RealTimePacer: sim time follows wall time; when behind, the debt is dropped and the
// achieved factor tells the truth.
#include <cmath>
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

// On another node's /clock, ticking 0.2 s at a time (a bag played at 20x): each tick is a
// debt of 0.2 s at once. A simulation that clears it before the next tick keeps up and
// drops nothing; counted as a debt beyond max_lag (0.1 s) it dropped nearly every tick and
// reached 0.02 of the clock (a probe, session 41). One that cannot clear it still drops.
TEST(RealTimePacer, OnACoarseClockATicksDebtIsNoLag) {
  for (const double step_cost : {0.002, 0.02}) {  // wall s per 10 ms step: 5x, 0.5x
    RealTimePacer pacer(0.1, 2.0);
    pacer.setLagByDuration(true);
    pacer.setFactor(1.0);
    pacer.restart(0.0, 0.0);
    // The clock runs at wall speed and reads 0.2 s x the ticks that have come.
    auto ticks = [](double wall) { return static_cast<long>(std::floor(wall * 5.0 + 1e-9)); };
    double wall = 0.0, sim = 0.0, clock = 0.0;
    while (wall < 20.0) {
      if (!pacer.shouldStep(clock, sim)) {
        wall = 0.2 * static_cast<double>(ticks(wall) + 1);  // wait for the next tick
      } else {
        wall += step_cost;
        sim += 0.01;
        pacer.afterStep(0.2 * static_cast<double>(ticks(wall)), sim, wall);
      }
      clock = 0.2 * static_cast<double>(ticks(wall));
    }
    if (step_cost < 0.01) {
      EXPECT_DOUBLE_EQ(pacer.droppedSimTime(), 0.0);
      EXPECT_NEAR(sim, clock, 0.2);
    } else {
      EXPECT_GT(pacer.droppedSimTime(), 5.0);
      EXPECT_NEAR(pacer.achievedFactor(), 0.5, 0.05);
    }
  }
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
