// The dam-break study compares resolutions, so each of its runs must hold the same water:
// the column a x 2a over the tank's depth, tiled exactly by its lattice. A spacing that does
// not divide the column leaves gaps the water spreads into, and that run's front lags for a
// reason that has nothing to do with the solver (0.0126 m held 8 % too little).

#include <gtest/gtest.h>

#include <vector>

#include "bench/BenchScenes.h"
#include "bench/DamBreakStudy.h"

namespace {

TEST(DamBreakStudy, EveryResolutionHoldsTheWholeColumn) {
  std::vector<pbf_bench::DamBreakResolution> all = pbf_bench::damBreakConvergence();
  for (const bool quick : {false, true})
    for (const pbf_bench::DamBreakResolution& res : pbf_bench::damBreakResolutions(quick)) all.push_back(res);
  {
    for (const pbf_bench::DamBreakResolution& res : all) {
      SCOPED_TRACE(res.label);
      const pbf::Scene scene = pbf_bench::damBreakScene(pbf_bench::defaultScenesDir(), res.spacing, res.depth);
      ASSERT_EQ(scene.fluid.size(), 1u);
      const Eigen::Vector3f column = scene.fluid[0].max - scene.fluid[0].min;
      const double d = res.spacing;
      std::vector<Eigen::Vector3f> x, v;
      scene.initialParticles(x, v);
      // The water the column holds, in lattice cells, against the particles placed.
      const double cells = double(column.x()) * column.y() * column.z() / (d * d * d);
      EXPECT_NEAR(double(x.size()), cells, 1e-3 * cells);
      // And it fills the column to every side: no gap to spread into.
      Eigen::Vector3f lo = x.front(), hi = x.front();
      for (const auto& p : x) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
      for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(lo[a] - scene.fluid[0].min[a], 0.5 * d, 1e-3 * d) << "axis " << a;
        EXPECT_NEAR(scene.fluid[0].max[a] - hi[a], 0.5 * d, 1e-3 * d) << "axis " << a;
      }
    }
  }
}

}  // namespace
