// SnapshotBuffer: the reader's snapshot stays valid and unchanged while the simulation
// writes newer ones.
#include <gtest/gtest.h>

#include "pbf_ros/core/PbfSolver.h"
#include "pbf_ros/ros/SnapshotBuffer.h"

namespace {
void fill(pbf::PbfSolver& solver, int n) {
  std::vector<Eigen::Vector3f> p;
  for (int i = 0; i < n; ++i) p.emplace_back(0.1f + 0.02f * (i % 10), 0.1f + 0.02f * (i / 10), 0.1f);
  solver.setContainer(Eigen::AlignedBox3f(Eigen::Vector3f::Zero(), Eigen::Vector3f::Ones()));
  solver.setParticles(p);
}
}  // namespace

TEST(SnapshotBuffer, EmptyUntilWrittenAndNoRateRequested) {
  pbf_ros::SnapshotBuffer buffer;
  EXPECT_EQ(buffer.latest(), nullptr);
  EXPECT_EQ(buffer.requestedRate(), 0.0);
}

TEST(SnapshotBuffer, ReaderKeepsItsSnapshotWhileNewerOnesAreWritten) {
  pbf::PbfSolver solver;
  fill(solver, 20);
  pbf_ros::SnapshotBuffer buffer;
  buffer.write(solver, 1.0, 0.0);
  auto held = buffer.latest();
  ASSERT_NE(held, nullptr);
  EXPECT_EQ(held->positions.size(), 20u);
  const std::uint64_t version = held->version;

  fill(solver, 30);
  buffer.write(solver, 2.0, 0.0);
  buffer.write(solver, 3.0, 0.0);
  EXPECT_EQ(held->version, version);      // untouched while held
  EXPECT_EQ(held->positions.size(), 20u);
  auto newest = buffer.latest();
  EXPECT_GT(newest->version, version);
  EXPECT_EQ(newest->positions.size(), 30u);
  EXPECT_DOUBLE_EQ(newest->stamp, 3.0);
}
