// The tank study's wall measures (pbf_bench --only tank), checked where the answer is known:
// a fresh lattice, one small step in, sits at rest density next to a face, an edge and a
// corner (the calibration), and its first layer half a spacing from every wall.

#include <gtest/gtest.h>

#include <cmath>

#include "bench/BenchScenes.h"
#include "bench/Hydrostatic.h"

namespace {

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
