// The scaling study times every size under one protocol (fixed dt, 4 iterations, no stop
// test), and a --set given to pbf_bench reaches it: until session 36 the study ignored
// --set without a word, so `--set gauss_seidel=false` timed the sweeps all the same.

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "bench/BenchScenes.h"
#include "bench/ScalingStudy.h"

namespace {

pbf_bench::BenchOptions options(const std::string& overrides) {
  pbf_bench::BenchOptions o;
  o.scenes_dir = pbf_bench::defaultScenesDir();
  o.solver_overrides = overrides;
  return o;
}

TEST(ScalingStudy, EverySizeRunsTheFixedProtocol) {
  const pbf::Scene scene = pbf_bench::scalingScene(options(""), 20000);
  EXPECT_FALSE(scene.solver.adaptive_time_step);
  EXPECT_FLOAT_EQ(scene.solver.time_step, 1.0f / 400.0f);
  EXPECT_EQ(scene.solver.min_iterations, 4);
  EXPECT_EQ(scene.solver.max_iterations, 4);
  EXPECT_EQ(scene.solver.density_tolerance, 0.0f);
  // The spacing gives the count asked for in the 0.16 m^3 column.
  std::vector<Eigen::Vector3f> x, v;
  scene.initialParticles(x, v);
  EXPECT_NEAR(double(x.size()), 20000.0, 0.05 * 20000.0);
}

TEST(ScalingStudy, SetOverridesReachTheStudyAfterItsProtocol) {
  const pbf::Scene plain = pbf_bench::scalingScene(options(""), 20000);
  const pbf::Scene jacobi =
      pbf_bench::scalingScene(options("gauss_seidel: false\nmax_iterations: 6\n"), 20000);
  EXPECT_NE(plain.solver.gauss_seidel, jacobi.solver.gauss_seidel);
  EXPECT_FALSE(jacobi.solver.gauss_seidel);
  EXPECT_EQ(jacobi.solver.max_iterations, 6);  // given last, over the protocol's 4
  EXPECT_EQ(jacobi.solver.min_iterations, 4);
  EXPECT_THROW(pbf_bench::scalingScene(options("no_such_key: 1\n"), 20000), std::exception);
}

TEST(ScalingStudy, LogLogSlopeOfAPowerLaw) {
  const std::vector<double> n = {20000, 40000, 80000, 160000, 320000};
  std::vector<double> t;
  for (double k : n) t.push_back(3e-4 * std::pow(k, 1.05));
  EXPECT_NEAR(pbf_bench::logLogSlope(n, t), 1.05, 1e-9);
}

}  // namespace
