// The free surface's lend (SolverParams::free_surface_lend, FreeSurfaceLend.h): a particle
// by a free surface is lent the density the air side would add were it fluid. It must lend
// the start lattice's top layer exactly its deficit and nothing at a wall, keep a resting
// tank at the level its volume implies, and give a buried particle's lend back.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "FreeSurfaceLend.h"
#include "SolverTestUtil.h"
#include "pbf_ros/core/Metrics.h"

namespace {

// The lattice particle nearest to `at`.
std::size_t nearest(const pbf::PbfSolver& solver, const Eigen::Vector3f& at) {
  std::size_t best = 0;
  for (std::size_t i = 0; i < solver.size(); ++i)
    if ((solver.positions()[i] - at).squaredNorm() < (solver.positions()[best] - at).squaredNorm()) best = i;
  return best;
}

}  // namespace

TEST(FreeSurfaceLend, TableIsCalibratedOnTheLatticeTopLayer) {
  const pbf::FreeSurfaceLend lend(0.02f, 0.04f);
  EXPECT_NEAR(lend.latticeTopDeficit(), 0.1135f, 5e-4f);
  EXPECT_NEAR(lend.latticeTopGradient() * 0.02f, 0.387f, 1e-3f);
  EXPECT_NEAR(lend.fraction(lend.latticeTopGradient()), lend.latticeTopDeficit(), 1e-4f);
  EXPECT_EQ(lend.fraction(0.0f), 0.0f);
  EXPECT_EQ(lend.fraction(std::nanf("")), 0.0f);
  float before = 0.0f;
  for (int k = 1; k <= 200; ++k) {  // up to well beyond the largest a plane surface gives
    const float f = lend.fraction(k * 0.005f / 0.02f);
    EXPECT_GE(f, before) << "the lend grows with the one-sided gradient";
    before = f;
  }
  EXPECT_LT(before, 0.5f);
  // The same at another spacing, in units of it: the lend means the same at every d.
  const pbf::FreeSurfaceLend coarse(0.04f, 0.08f);
  EXPECT_NEAR(coarse.fraction(0.3f / 0.04f), lend.fraction(0.3f / 0.02f), 1e-5f);
}

// A fresh lattice with a free top, gravity off: with the lend, its top layer sums to rho0
// like the rest (without it 0.886 rho0), and particles by the walls are lent nothing (their
// own images, which count twice in the constraint, are the lattice beyond the wall).
TEST(FreeSurfaceLend, FreshLatticeSumsToRestDensityAtItsSurfaceAndWalls) {
  pbf::Scene scene = pbf_test::loadScene("hydrostatic_tank");
  scene.solver.particle_spacing = 0.04f;
  scene.solver.gravity.setZero();
  scene.solver.xsph_viscosity = 0.0f;
  scene.fluid[0].max.z() = 0.28f;  // whole layers of 0.04 m
  const float d = scene.solver.particle_spacing;
  const float top = scene.fluid[0].max.z() - 0.5f * d, mid = 0.2f - 0.5f * d;
  const std::vector<std::pair<const char*, Eigen::Vector3f>> where = {
      {"top layer", {mid, mid, top}},          {"top layer by a wall", {0.5f * d, mid, top}},
      {"top layer in a corner", {0.5f * d, 0.5f * d, top}}, {"floor", {mid, mid, 0.5f * d}},
      {"floor corner", {0.5f * d, 0.5f * d, 0.5f * d}},   {"interior", {mid, mid, 3.5f * d}}};
  for (const bool lend : {false, true}) {
    scene.solver.free_surface_lend = lend;
    auto solver = pbf_test::makeSolver(scene);
    solver->stepWith(1e-4f);
    for (const auto& [name, at] : where) {
      const std::size_t i = nearest(*solver, at);
      ASSERT_LT((solver->positions()[i] - at).norm(), 1e-3f * d) << name;
      const float rho = solver->densities()[i] / scene.solver.rest_density;
      std::printf("lend %s, %s: %.4f rho0\n", lend ? "on" : "off", name, rho);
      const bool top_layer = std::string(name).rfind("top layer", 0) == 0;
      if (lend || !top_layer)
        EXPECT_NEAR(rho, 1.0f, 2e-3f) << name;
      else
        EXPECT_LT(rho, 0.9f) << name << ": the truncated sum the lend makes up";
    }
  }
}

// A fresh lattice is lent where it entered the fluid, not where the first step's gravity
// pushed it: in one step of 1/60 s the shipped tank's column moves 0.136 d into the floor,
// which makes the layers over it one-sided. Measured there (until session 37), the floor's
// layers were lent as if they were a free surface and looked compressed by up to 27 %. Lent
// at the start positions, the floor and the interior are lent nothing at every step, and
// the top layer its deficit.
TEST(FreeSurfaceLend, FirstStepLendsTheLatticeAsItStartsWhateverTheStep) {
  pbf::Scene scene = pbf_test::loadScene("hydrostatic_tank");
  const float d = scene.solver.particle_spacing, rho0 = scene.solver.rest_density;
  const pbf::FreeSurfaceLend table(d, scene.solver.supportRadius());
  for (const float dt : {1e-4f, 1.0f / 240.0f, 1.0f / 60.0f}) {
    auto solver = pbf_test::makeSolver(scene);
    float top_z = -1e9f;
    for (const auto& p : scene.fluid) top_z = std::max(top_z, p.max.z() - 0.5f * d);
    solver->stepWith(dt);
    double floor_lend = 0.0, top_lend = 0.0;
    int floor_count = 0, top_count = 0;
    for (std::size_t i = 0; i < solver->size(); ++i) {
      const float z = solver->positions()[i].z();
      const float lend = solver->surfaceLend(i) / rho0;
      if (z < 1.5f * d) {  // the two layers over the floor
        floor_lend = std::max<double>(floor_lend, lend);
        ++floor_count;
      } else if (z > top_z - 0.5f * d) {
        top_lend += lend;
        ++top_count;
      }
    }
    ASSERT_GT(floor_count, 0);
    ASSERT_GT(top_count, 0);
    std::printf("dt %.5f s: largest lend over the floor %.5f rho0, mean lend of the top layer %.4f rho0\n",
                dt, floor_lend, top_lend / top_count);
    EXPECT_LT(floor_lend, 1e-3) << "dt " << dt << ": the floor's layers are not a free surface";
    EXPECT_NEAR(top_lend / top_count, table.latticeTopDeficit(), 0.01) << "dt " << dt;
  }
}

// The shipped tank (d = 0.02 m) solved to 0.03 %: without the lend its top layer sinks
// into the second's hollows and the free surface (the colour field's half level) falls
// 0.55-0.65 % short of what the volume implies; with it, 0.35-0.4 %. What the lend does not
// hold is the bulk's: the cubic start lattice relaxes into a packing 0.3 % denser at the same
// kernel sum, in a closed box filled to its lid as well (doc/calibration.md, the start-up).
// That relaxation is chaotic: which packing forms moves a level by 0.1-0.3 points with any
// change at float level (a tolerance 3 % different, another CPU's rsqrt), as much as the
// lend's own effect in a single run (0.17-0.47 points over seven runs on one host). So the
// lend's effect is taken as the mean over two solves (0.030 and 0.031 %), two packings.
TEST(FreeSurfaceLend, RestingTankKeepsTheLevelItsVolumeImplies) {
  pbf::Scene scene = pbf_test::loadScene("hydrostatic_tank");
  double mean_level[2] = {0.0, 0.0};  // lend off, on
  for (const float tolerance : {3e-4f, 3.1e-4f}) {
    scene.solver.density_tolerance = tolerance;
    for (const bool lend : {false, true}) {
      scene.solver.free_surface_lend = lend;
      auto solver = pbf_test::makeSolver(scene);
      while (solver->time() < 1.5) ASSERT_FALSE(solver->step().failed);
      const double level = pbf::freeSurfaceHeight(solver->positions(), scene.solver.particle_spacing,
                                                  scene.container) / pbf_test::impliedLevel(*solver, scene);
      std::printf("shipped tank at %.3f %%, 1.5 s, lend %s: level %.4f of the implied\n",
                  100.0 * tolerance, lend ? "on" : "off", level);
      if (lend) EXPECT_NEAR(level, 1.0, 0.005);
      mean_level[lend] += 0.5 * level;
    }
  }
  EXPECT_GT(mean_level[1] - mean_level[0], 0.0015) << "the lend is what holds the top layer up";
}

// A block dropped onto another buries the lower block's lent top layer: those particles
// give their lend back, so the settled column holds the level its volume implies. (Kept,
// the buried layer's lend held its neighbours apart and raised the level by 5.7 %; a lend
// that follows the gradient both ways raised it by 2.1 %, and the resting tank's by 0.8 %.)
TEST(FreeSurfaceLend, ABuriedParticleGivesItsLendBack) {
  pbf::Scene scene = pbf_test::loadScene("hydrostatic_tank");
  scene.solver.particle_spacing = 0.04f;
  scene.solver.density_tolerance = 3e-4f;
  scene.solver.free_surface_lend = true;
  scene.fluid[0].max.z() = 0.16f;
  pbf::FluidBlock upper = scene.fluid[0];
  upper.min.z() = 0.24f;
  upper.max.z() = 0.40f;
  scene.fluid.push_back(upper);
  auto solver = pbf_test::makeSolver(scene);
  while (solver->time() < 3.0) ASSERT_FALSE(solver->step().failed);
  const double level = pbf::freeSurfaceHeight(solver->positions(), scene.solver.particle_spacing,
                                              scene.container) / pbf_test::impliedLevel(*solver, scene);
  std::printf("block dropped on a block, d = 0.04 m, 3 s: level %.4f of the implied\n", level);
  EXPECT_NEAR(level, 1.0, 0.005);
}

// h = d (the smallest support the parameters allow) reaches no neighbour on the lattice:
// nothing is missing at a surface, so nothing is lent, and turning the option on works.
TEST(FreeSurfaceLend, SupportOfOneSpacingLendsNothing) {
  const pbf::FreeSurfaceLend lend(0.02f, 0.02f);
  EXPECT_EQ(lend.fraction(10.0f), 0.0f);
  pbf::Scene scene = pbf_test::loadScene("hydrostatic_tank");
  scene.solver.particle_spacing = 0.04f;
  scene.solver.support_radius_factor = 1.0f;
  scene.solver.free_surface_lend = true;
  auto solver = pbf_test::makeSolver(scene);
  EXPECT_FALSE(solver->step().failed);
}
