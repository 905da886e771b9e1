// A solver step allocates nothing on the heap once its buffers have grown (issue 10:
// persistent buffers, no allocation in a step). Counted by replacing the global operator
// new in this test binary only; OpenMP's runtime allocates with malloc and is not counted.

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "SolverTestUtil.h"

namespace {
std::atomic<long> g_allocations{0};
}  // namespace

void* operator new(std::size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size != 0 ? size : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace {

TEST(StepAllocations, AWarmStepAllocatesNothing) {
  // The resting tank keeps its neighbour count, so no buffer has to grow again once warm;
  // a step's results (and so its buffer sizes) are the same on every run.
  pbf::Scene scene = pbf_test::loadScene("hydrostatic_tank");
  scene.solver.particle_spacing = 0.04f;
  auto solver = pbf_test::makeSolver(scene);
  for (int s = 0; s < 30; ++s) solver->step();
  const long before = g_allocations.load();
  for (int s = 0; s < 20; ++s) {
    const pbf::StepStats stats = solver->step();
    ASSERT_FALSE(stats.failed);
  }
  EXPECT_EQ(g_allocations.load() - before, 0) << "heap allocations in 20 warm steps";
}

TEST(StepAllocations, SkippedStagesNameTheirStagesInOrder) {
  pbf::SkippedStages stages;
  EXPECT_TRUE(stages.names().empty());
  stages.add(pbf::SkippedStages::kWrench);
  stages.add(pbf::SkippedStages::kVorticity);
  stages.add(pbf::SkippedStages::kIterationsAfterTolerance);
  EXPECT_TRUE(stages.has(pbf::SkippedStages::kVorticity));
  EXPECT_FALSE(stages.has(pbf::SkippedStages::kXsph));
  EXPECT_EQ(stages.names(),
            (std::vector<std::string>{"vorticity", "iterations_after_tolerance", "wrench"}));
}

}  // namespace
