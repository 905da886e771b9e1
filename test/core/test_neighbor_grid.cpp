// The grid's neighbour lists equal brute force, for awkward inputs too.

#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <random>
#include <set>

#include "pbf_ros/core/NeighborGrid.h"

namespace {

using Points = std::vector<Eigen::Vector3f>;

// Neighbour sets in terms of the caller's original indices.
std::vector<std::set<std::uint32_t>> gridNeighbors(const Points& pts, float radius,
                                                    const Eigen::AlignedBox3f& domain = {}) {
  pbf::NeighborGrid grid;
  const auto order = grid.build(pts, radius, domain);
  Points sorted(pts.size());
  for (std::size_t k = 0; k < pts.size(); ++k) sorted[k] = pts[order[k]];
  grid.findNeighbors(sorted, radius);
  std::vector<std::set<std::uint32_t>> out(pts.size());
  for (std::size_t k = 0; k < pts.size(); ++k) {
    for (std::uint32_t e = grid.offsets()[k]; e < grid.offsets()[k + 1]; ++e)
      out[order[k]].insert(order[grid.indices()[e]]);
    EXPECT_TRUE(std::is_sorted(grid.indices().begin() + grid.offsets()[k],
                               grid.indices().begin() + grid.offsets()[k + 1]));
  }
  return out;
}

std::vector<std::set<std::uint32_t>> bruteForce(const Points& pts, float radius) {
  std::vector<std::set<std::uint32_t>> out(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i)
    for (std::size_t j = 0; j < pts.size(); ++j)
      if (i != j && (pts[i] - pts[j]).squaredNorm() < radius * radius) out[i].insert(j);
  return out;
}

TEST(NeighborGrid, EqualsBruteForceOnRandomPointsWithNegativeCoordinates) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.3f, 0.7f);
  Points pts(3000);
  for (auto& p : pts) p = Eigen::Vector3f(u(rng), u(rng), u(rng));
  for (float radius : {0.05f, 0.13f})
    EXPECT_EQ(gridNeighbors(pts, radius), bruteForce(pts, radius)) << "radius " << radius;
}

TEST(NeighborGrid, EqualsBruteForceWithPointsExactlyOnCellBordersAndCoincident) {
  const float radius = 0.25f;
  Points pts;
  // A lattice whose spacing is the cell size: every point sits exactly on cell borders,
  // and pairs exactly `radius` apart must be excluded (strictly closer only).
  for (int x = -3; x <= 3; ++x)
    for (int y = -3; y <= 3; ++y)
      for (int z = -2; z <= 2; ++z) pts.emplace_back(x * radius, y * radius, z * radius * 0.5f);
  // Coincident groups, including on a border.
  for (int c = 0; c < 5; ++c) pts.emplace_back(0.0f, 0.0f, 0.0f);
  for (int c = 0; c < 3; ++c) pts.emplace_back(0.1f, -0.2f, 0.3f);
  EXPECT_EQ(gridNeighbors(pts, radius), bruteForce(pts, radius));
}

TEST(NeighborGrid, EqualsBruteForceWhenPointsLieOutsideTheGivenDomain) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-2.0f, 2.0f);
  Points pts(1500);
  for (auto& p : pts) p = Eigen::Vector3f(u(rng), u(rng), u(rng));
  const Eigen::AlignedBox3f domain(Eigen::Vector3f(-0.5f, -0.5f, -0.5f), Eigen::Vector3f(0.5f, 0.5f, 0.5f));
  EXPECT_EQ(gridNeighbors(pts, 0.2f, domain), bruteForce(pts, 0.2f));
}

TEST(NeighborGrid, AllPointsAtOnePointAreAllNeighbours) {
  const Points pts(200, Eigen::Vector3f(0.3f, -0.1f, 2.0f));
  const auto n = gridNeighbors(pts, 0.1f);
  for (const auto& s : n) EXPECT_EQ(s.size(), pts.size() - 1);
}

TEST(NeighborGrid, ListsDoNotDependOnThreadCount) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  Points pts(20000);
  for (auto& p : pts) p = Eigen::Vector3f(u(rng), u(rng), u(rng));
  std::vector<std::uint32_t> off[2], idx[2], order[2];
  for (int t = 1; t <= 2; ++t) {
    omp_set_num_threads(t);
    pbf::NeighborGrid grid;
    order[t - 1] = grid.build(pts, 0.06f);
    Points sorted(pts.size());
    for (std::size_t k = 0; k < pts.size(); ++k) sorted[k] = pts[order[t - 1][k]];
    grid.findNeighbors(sorted, 0.06f);
    off[t - 1] = grid.offsets();
    idx[t - 1] = grid.indices();
  }
  omp_set_num_threads(omp_get_num_procs());
  EXPECT_EQ(order[0], order[1]);
  EXPECT_EQ(off[0], off[1]);
  EXPECT_EQ(idx[0], idx[1]);
}

TEST(NeighborGrid, MortonInterleavesBits) {
  EXPECT_EQ(pbf::NeighborGrid::morton3(1, 0, 0), 1u);
  EXPECT_EQ(pbf::NeighborGrid::morton3(0, 1, 0), 2u);
  EXPECT_EQ(pbf::NeighborGrid::morton3(0, 0, 1), 4u);
  EXPECT_EQ(pbf::NeighborGrid::morton3(3, 3, 3), 63u);
}

}  // namespace
