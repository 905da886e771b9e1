// The dam-break study's two surge-front measures (src/tools/bench/SurfaceMetrics.h) where
// the answer is known: a lattice face, droplets and a detached body ahead of the surge, and
// a surge tip that thins, which the slab front sees in steps and the sliding front follows.

#include <gtest/gtest.h>

#include <vector>

#include "bench/SurfaceMetrics.h"

namespace {

using Positions = std::vector<Eigen::Vector3f>;

constexpr float kD = 0.02f;
// A tank 1 m long and 0.2 m wide (10 particles per row), floor at z = 0.
const Eigen::AlignedBox3f kTank(Eigen::Vector3f(0.0f, 0.0f, 0.0f), Eigen::Vector3f(1.0f, 0.2f, 0.5f));

// Columns 0 .. columns-1 of a lattice against the back wall, `layers` high, centred in
// their slabs (x = (i + 1/2) d), as the scenes place them.
Positions block(int columns, int layers, float x_offset = 0.0f) {
  Positions p;
  for (int i = 0; i < columns; ++i)
    for (int j = 0; j < 10; ++j)
      for (int k = 0; k < layers; ++k)
        p.emplace_back((i + 0.5f) * kD + x_offset, (j + 0.5f) * kD, (k + 0.5f) * kD);
  return p;
}

TEST(SurgeFront, BothFrontsFindALatticeFace) {
  const Positions p = block(15, 4);
  EXPECT_NEAR(pbf_bench::surgeFront(p, kD, kTank), 15 * kD, 1e-6);
  EXPECT_NEAR(pbf_bench::surgeFrontSliding(p, kD, kTank), 15 * kD, 1e-6);
}

TEST(SurgeFront, DropletsAndADetachedBodyDoNotCount) {
  Positions p = block(15, 4);
  // Three droplets just ahead (fewer than half a row in any one spacing) ...
  for (int k = 0; k < 3; ++k) p.emplace_back((15.5f + k) * kD, 0.1f, 0.01f);
  // ... and a whole body three spacings beyond the face: a gap wider than one spacing.
  for (int j = 0; j < 10; ++j) p.emplace_back(18.5f * kD, (j + 0.5f) * kD, 0.01f);
  EXPECT_NEAR(pbf_bench::surgeFront(p, kD, kTank), 15 * kD, 1e-6);
  EXPECT_NEAR(pbf_bench::surgeFrontSliding(p, kD, kTank), 15 * kD, 1e-6);
  // Nothing attached to the back wall: no front at all.
  EXPECT_EQ(pbf_bench::surgeFront(block(5, 2, 0.2f), kD, kTank), 0.0);
  EXPECT_EQ(pbf_bench::surgeFrontSliding(block(5, 2, 0.2f), kD, kTank), 0.0);
}

TEST(SurgeFront, TheSlidingFrontFollowsATipThatTheSlabsSeeInSteps) {
  // The last full row moves ahead by a fraction of a spacing: the sliding front moves with
  // it, the slab front only when the row crosses into the next slab.
  for (const float shift : {0.1f, 0.3f, 0.45f}) {
    Positions p = block(15, 4);
    for (int j = 0; j < 10; ++j) p.emplace_back((15.5f + shift) * kD, (j + 0.5f) * kD, 0.01f);
    EXPECT_NEAR(pbf_bench::surgeFrontSliding(p, kD, kTank), (16.0f + shift) * kD, 1e-6) << shift;
    EXPECT_NEAR(pbf_bench::surgeFront(p, kD, kTank), (shift < 0.5f ? 16 : 17) * kD, 1e-6) << shift;
  }
}

}  // namespace
