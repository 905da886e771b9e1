// Solids far from the fluid cost nothing and change nothing: a column of 30 robot-link-like
// solids beside a tank leaves the simulation bit for bit as it was without them (they are
// left out of every per-particle test: Boundaries.h keepOnlyObstaclesNear), while a solid
// within the kernel's reach of the fluid box still takes part.

#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <limits>

#include "SolverTestUtil.h"
#include "pbf_ros/core/Boundaries.h"
#include "pbf_ros/core/LatticeBoundary.h"

namespace {

TEST(FarSolids, ThirtyLinksBesideTheTankChangeNothing) {
  omp_set_num_threads(1);  // the same summation order in both runs
  pbf::Scene scene = pbf_test::loadScene("hydrostatic_tank");
  scene.solver.particle_spacing = 0.04f;
  scene.fluid[0].velocity = Eigen::Vector3f(0.3f, 0.0f, 0.0f);  // a sloshing start: things move
  auto plain = pbf_test::makeSolver(scene);
  for (int k = 0; k < 30; ++k) {
    pbf::Obstacle o;
    o.shape = k % 2 ? pbf::Obstacle::Shape::Box : pbf::Obstacle::Shape::Cylinder;
    o.half_extents = Eigen::Vector3f(0.03f, 0.03f, 0.05f);
    o.radius = 0.03f;
    o.half_length = 0.05f;
    // Beside the container (0.4 m wide), 30-50 cm beyond its wall: out of the fluid's reach.
    o.pose.translation() = Eigen::Vector3f(scene.container.max().x() + 0.3f + 0.1f * (k % 3), 0.2f,
                                           0.05f + 0.1f * (k / 3));
    scene.obstacles.push_back(o);
  }
  auto with_robot = pbf_test::makeSolver(scene);
  for (int s = 0; s < 60; ++s) {
    plain->step();
    with_robot->step();
  }
  ASSERT_EQ(plain->size(), with_robot->size());
  for (std::size_t i = 0; i < plain->size(); ++i) ASSERT_EQ(plain->positions()[i], with_robot->positions()[i]) << i;
  omp_set_num_threads(omp_get_num_procs());
}

TEST(FarSolids, OnlySolidsWithinReachOfTheFluidTakePart) {
  const pbf::LatticeBoundary lattice(0.02f, 0.04f);
  std::vector<pbf::Obstacle> obstacles(3);
  for (auto& o : obstacles) {
    o.shape = pbf::Obstacle::Shape::Sphere;
    o.radius = 0.05f;
  }
  const Eigen::AlignedBox3f fluid(Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(1, 1, 1));
  obstacles[0].pose.translation() = Eigen::Vector3f(0.5f, 0.5f, 0.5f);                       // inside
  obstacles[1].pose.translation() = Eigen::Vector3f(1.0f + 0.05f + lattice.reach() - 1e-3f, 0.5f, 0.5f);  // reaches in
  obstacles[2].pose.translation() = Eigen::Vector3f(1.0f + 0.05f + lattice.reach() + 0.1f, 0.5f, 0.5f);  // does not
  pbf::SolidBoundaries solids(Eigen::AlignedBox3f(), Eigen::Isometry3f::Identity(), obstacles, lattice, 0.01f);
  solids.keepOnlyObstaclesNear(fluid);
  // A point at the box's face sees obstacle 1's density but never obstacle 2's.
  float fraction = 0.0f;
  Eigen::Vector3f gradient = Eigen::Vector3f::Zero();
  EXPECT_TRUE(solids.density(Eigen::Vector3f(1.0f, 0.5f, 0.5f), fraction, gradient));
  std::vector<int> parts;
  solids.densityGradientParts(Eigen::Vector3f(1.0f, 0.5f, 0.5f), [&](int solid, const Eigen::Vector3f&) {
    parts.push_back(solid);
  });
  EXPECT_EQ(parts, std::vector<int>{pbf::SolidBoundaries::kContainerFaces + 1});
  // A particle that did get inside obstacle 2 (outside the box it was told about) is not
  // pushed out: it was left out.
  const Eigen::Vector3f inside_far = obstacles[2].pose.translation();
  EXPECT_EQ(solids.project(inside_far), inside_far);
}

// With no obstacle near, projecting is an inline clamp into the container (Boundaries.h).
// It must do exactly what the general path does, and leave a NaN for the step to reject.
TEST(FarSolids, WithNoSolidNearProjectingIsTheSameClampAndKeepsNaN) {
  const pbf::LatticeBoundary lattice(0.02f, 0.04f);
  const Eigen::AlignedBox3f container(Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(1, 1, 1));
  std::vector<pbf::Obstacle> obstacles(1);
  obstacles[0].shape = pbf::Obstacle::Shape::Sphere;
  obstacles[0].radius = 0.01f;
  obstacles[0].pose.translation() = Eigen::Vector3f(0.9f, 0.9f, 0.9f);  // near the fluid, far from the points
  pbf::SolidBoundaries clamp_only(container, Eigen::Isometry3f::Identity(), obstacles, lattice, 0.01f);
  clamp_only.keepOnlyObstaclesNear(Eigen::AlignedBox3f(Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(0.2f, 0.2f, 0.2f)));
  const pbf::SolidBoundaries general(container, Eigen::Isometry3f::Identity(), obstacles, lattice, 0.01f);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<Eigen::Vector3f> points = {{0.1f, 0.2f, 0.3f},   {-0.5f, 0.2f, 1.7f}, {0.005f, 0.995f, 0.5f},
                                               {nan, 0.2f, 0.3f},    {0.1f, nan, 2.0f},   {-1.0f, -1.0f, nan},
                                               {0.01f, 0.99f, 0.0f}};
  for (const Eigen::Vector3f& p : points) {
    const Eigen::Vector3f a = clamp_only.project(p), b = general.project(p);
    if (!p.allFinite()) {  // still not finite, for the step to reject
      EXPECT_TRUE(std::isnan(a.x()) || std::isnan(a.y()) || std::isnan(a.z())) << p.transpose();
      continue;
    }
    EXPECT_EQ(a, b) << p.transpose();
    EXPECT_TRUE((a.array() >= 0.01f).all() && (a.array() <= 0.99f).all()) << a.transpose();
  }
  EXPECT_EQ(clamp_only.project(Eigen::Vector3f(-0.5f, 0.2f, 1.7f)), Eigen::Vector3f(0.01f, 0.2f, 0.99f));
  float fraction = 0.0f;
  Eigen::Vector3f gradient = Eigen::Vector3f::Zero();
  EXPECT_FALSE(clamp_only.density(Eigen::Vector3f(0.9f, 0.9f, 0.9f), fraction, gradient));
  EXPECT_TRUE(general.density(Eigen::Vector3f(0.9f, 0.9f, 0.92f), fraction, gradient));
}

}  // namespace
