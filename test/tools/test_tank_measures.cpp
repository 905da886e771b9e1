// The tank study's wall measures (pbf_bench --only tank), checked where the answer is known:
// a fresh lattice, one small step in, sits at rest density next to a face, an edge and a
// corner (the calibration), and its first layer half a spacing from every wall. And the
// free surface gauge (pbf::freeSurfaceHeight) on particle states whose level is known.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "bench/BenchScenes.h"
#include "bench/Hydrostatic.h"
#include "pbf_ros/core/Metrics.h"

namespace {

const Eigen::AlignedBox3f kTank(Eigen::Vector3f(0.0f, 0.0f, 0.0f), Eigen::Vector3f(0.4f, 0.4f, 0.6f));

// The tank's start lattice: water 0.3 m deep on its 0.4 x 0.4 m floor at spacing d.
std::vector<Eigen::Vector3f> tankLattice(float d) {
  std::vector<Eigen::Vector3f> x;
  const int n = static_cast<int>(std::lround(0.4 / d)), layers = static_cast<int>(std::lround(0.3 / d));
  for (int k = 0; k < layers; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) x.emplace_back((i + 0.5f) * d, (j + 0.5f) * d, (k + 0.5f) * d);
  return x;
}

TEST(FreeSurfaceGauge, AStartLatticeReadsItsOwnLevelAtEverySpacing) {
  for (const float d : {0.05f, 0.025f, 0.02f, 0.0125f, 0.01f})  // each tiles the water
    EXPECT_NEAR(pbf::freeSurfaceHeight(tankLattice(d), d, kTank), 0.3, 1e-6) << "d = " << d;
}

// A settled tank's top layer is rough: its particles stand up to ~0.3 d above and below the
// layer's mean. Where the volume sits is the mean; each column's highest particle stands
// above it, and the gauge of sessions up to 29 (that particle plus d/2) read high.
TEST(FreeSurfaceGauge, ARoughTopLayerReadsWhereItsVolumeSits) {
  const float d = 0.02f;
  std::vector<Eigen::Vector3f> x = tankLattice(d);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> jitter(0.0f, 0.3f * d);
  bool up = true;  // alternately up and down by the same draw: the layer's mean stays put
  float amount = 0.0f;
  for (auto& p : x)
    if (p.z() > 0.3f - d) {
      if (up) amount = jitter(rng);
      p.z() += up ? amount : -amount;
      up = !up;
    }
  const double level = pbf::freeSurfaceHeight(x, d, kTank);
  EXPECT_NEAR(level, 0.3, 0.02 * d);
  // The highest particle of each 2d column plus d/2 (the old gauge), median over columns.
  std::vector<float> top(100, 0.0f);
  for (const auto& p : x) {
    float& t = top[std::min(9, static_cast<int>(p.y() / (2 * d))) * 10 + std::min(9, static_cast<int>(p.x() / (2 * d)))];
    t = std::max(t, p.z());
  }
  std::nth_element(top.begin(), top.begin() + 50, top.end());
  EXPECT_GT(top[50] + 0.5f * d - 0.3f, 0.1f * d) << "the highest particles read high";
}

// A column compressed by 1 % (every height scaled by 0.99) reads a 1 % lower level.
TEST(FreeSurfaceGauge, ACompressedColumnReadsItsLowerLevel) {
  const float d = 0.0125f;
  std::vector<Eigen::Vector3f> x = tankLattice(d);
  for (auto& p : x) p.z() *= 0.99f;
  EXPECT_NEAR(pbf::freeSurfaceHeight(x, d, kTank), 0.297, 0.02 * d);
}

// Drops above the water (one over every column, five spacings up) do not raise the level.
TEST(FreeSurfaceGauge, DropsAboveTheWaterDoNotCount) {
  const float d = 0.02f;
  std::vector<Eigen::Vector3f> x = tankLattice(d);
  for (int j = 0; j < 5; ++j)
    for (int i = 0; i < 5; ++i) x.emplace_back((4 * i + 2) * d, (4 * j + 2) * d, 0.3f + 5 * d);
  EXPECT_NEAR(pbf::freeSurfaceHeight(x, d, kTank), 0.3, 0.01 * d);
}

TEST(TankMeasures, AFreshLatticeSitsAtRestDensityAgainstEveryWall) {
  // 0.05 m tiles the tank's water (0.4 x 0.4 x 0.3 m) exactly: 8 x 8 x 6 particles.
  pbf::Scene scene = pbf_bench::hydrostaticScene(pbf_bench::defaultScenesDir(), 0.05f);
  scene.solver.adaptive_time_step = false;
  scene.solver.time_step = 1.0e-4f;  // one step: gravity moves the lattice by 5e-8 m
  const pbf_bench::HydrostaticResult r = pbf_bench::runHydrostatic(scene, 1.0e-4, nullptr);
  EXPECT_EQ(r.totals.steps, 1);
  EXPECT_NEAR(r.interior_density, 1.0, 1e-3);
  EXPECT_NEAR(r.face_density, 1.0, 1e-3);
  EXPECT_NEAR(r.edge_density, 1.0, 1e-3);
  EXPECT_NEAR(r.corner_density, 1.0, 1e-3);
  EXPECT_NEAR(r.floor_density, 1.0, 1e-3);
  EXPECT_NEAR(r.bottom_edge_density, 1.0, 1e-3);
  EXPECT_NEAR(r.second_layer_inside_density, 1.0, 1e-3);
  EXPECT_NEAR(r.wall_gap, 0.5, 1e-3);
  EXPECT_LT(r.startup_speed_max, 2.0 * 9.81 * 1.0e-4);  // about g dt: gravity alone
  EXPECT_EQ(r.first_steps_speed_max, r.startup_speed_max);  // one step is all of both windows
  EXPECT_NEAR(r.height_loss, 0.0, 1e-3);
  EXPECT_NEAR(r.mean_height_loss, 0.0, 1e-4);
  // 4 x 4 columns of 2 layers between lattice planes: exactly one particle per d^3.
  EXPECT_NEAR(r.bulk_number_density, 1.0, 1e-9);
}

TEST(TankMeasures, ALayerThatLeavesAWallIsSeen) {
  // The same lattice shifted 1.2 spacings off the floor: no particle within a spacing of it.
  pbf::Scene scene = pbf_bench::hydrostaticScene(pbf_bench::defaultScenesDir(), 0.05f);
  for (auto& block : scene.fluid) {
    block.min.z() += 0.06f;
    block.max.z() += 0.06f;
  }
  scene.solver.adaptive_time_step = false;
  scene.solver.time_step = 1.0e-4f;
  const pbf_bench::HydrostaticResult r = pbf_bench::runHydrostatic(scene, 1.0e-4, nullptr);
  EXPECT_TRUE(std::isinf(r.wall_gap)) << r.wall_gap;
  // Nothing lies on the floor, and its lowest layer is now the one "one spacing higher".
  EXPECT_TRUE(std::isnan(r.floor_density)) << r.floor_density;
  EXPECT_TRUE(std::isnan(r.bottom_edge_density)) << r.bottom_edge_density;
  EXPECT_FALSE(std::isnan(r.second_layer_inside_density));
}

TEST(TankMeasures, TheBulkCountIsPerVolumeOfTheRegion) {
  // Water over half the bulk region's width (x < 0.2 m of its 0.1-0.3 m): half the count.
  pbf::Scene scene = pbf_bench::hydrostaticScene(pbf_bench::defaultScenesDir(), 0.05f);
  for (auto& block : scene.fluid) block.max.x() = 0.2f;
  scene.solver.adaptive_time_step = false;
  scene.solver.time_step = 1.0e-4f;
  const pbf_bench::HydrostaticResult r = pbf_bench::runHydrostatic(scene, 1.0e-4, nullptr);
  EXPECT_NEAR(r.bulk_number_density, 0.5, 1e-9);
}

}  // namespace
