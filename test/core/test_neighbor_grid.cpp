// The grid's neighbour lists equal brute force, for awkward inputs too.

#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>

#include "CandidateFilter.h"
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

// The wide (AVX2) filter must keep exactly the pairs the scalar one keeps, also at distances
// that round to the radius, for every count modulo the group width and with `self` inside.
TEST(CandidateFilter, BothBuildsKeepTheSamePairs) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-0.1f, 0.1f);
  const float radius = 0.08f, r2 = radius * radius;
  std::size_t kept_total = 0;
  for (std::size_t count = 0; count < 70; ++count) {
    const std::size_t padded = (count + pbf::kCandidatePadding - 1) / pbf::kCandidatePadding *
                               pbf::kCandidatePadding;
    std::vector<float> x(padded, INFINITY), y(padded, INFINITY), z(padded, INFINITY);
    std::vector<std::uint32_t> index(padded, 0);
    for (std::size_t k = 0; k < count; ++k) {
      x[k] = u(rng), y[k] = u(rng), z[k] = u(rng);
      if (k % 3 == 0) {  // exactly on, or an ulp either side of, the sphere along x
        const float off[3] = {std::nextafter(radius, 0.0f), radius, std::nextafter(radius, 1.0f)};
        x[k] = off[k % 9 / 3], y[k] = 0.0f, z[k] = 0.0f;
      }
      index[k] = static_cast<std::uint32_t>(3 * k + 1);
    }
    const std::uint32_t self = count > 0 ? index[count / 2] : 7;
    const pbf::Candidates c{x.data(), y.data(), z.data(), index.data(), count};
    std::vector<std::uint32_t> wide(padded + pbf::kCandidatePadding), scalar(wide.size());
    const std::size_t n_wide = pbf::keepCandidatesWithin(c, 0.0f, 0.0f, 0.0f, r2, self, wide.data());
    const std::size_t n_scalar = pbf::keepCandidatesWithinScalar(c, 0.0f, 0.0f, 0.0f, r2, self, scalar.data());
    ASSERT_EQ(n_wide, n_scalar) << "count " << count << " (" << pbf::candidateFilterVariant() << ")";
    wide.resize(n_wide);
    scalar.resize(n_scalar);
    EXPECT_EQ(wide, scalar) << "count " << count;
    std::vector<std::uint32_t> expected;  // brute force, in candidate order
    for (std::size_t k = 0; k < count; ++k)
      if (index[k] != self && x[k] * x[k] + y[k] * y[k] + z[k] * z[k] < r2) expected.push_back(index[k]);
    EXPECT_EQ(scalar, expected) << "count " << count;
    kept_total += n_scalar;
  }
  EXPECT_GT(kept_total, 100u);  // the test kept and dropped pairs
}

// Gathering a cell's candidates: both builds keep the same points, in index order, and
// never drop a point that lies within the radius of a point in the box (the corners and
// faces included, and points an ulp either side of the radius from them), nor keep one
// farther than the radius from the whole box.
TEST(CandidateFilter, GatheringNearABoxDropsNoPointNearTheBox) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-0.2f, 0.2f);
  const float radius = 0.08f, r2 = radius * radius;
  const float lo[3] = {-0.013f, 0.002f, -0.021f}, hi[3] = {0.017f, 0.031f, 0.0f};
  std::vector<Eigen::Vector3f> inside;  // corners, face centres and random points of the box
  for (int k = 0; k < 8; ++k) inside.emplace_back(k & 1 ? hi[0] : lo[0], k & 2 ? hi[1] : lo[1], k & 4 ? hi[2] : lo[2]);
  for (int k = 0; k < 40; ++k) {
    Eigen::Vector3f p;
    for (int a = 0; a < 3; ++a) p[a] = lo[a] + (hi[a] - lo[a]) * (u(rng) + 0.2f) / 0.4f;
    if (k < 6) p[k / 2] = k % 2 ? hi[k / 2] : lo[k / 2];
    inside.push_back(p);
  }
  std::size_t near_total = 0, dropped_total = 0;
  for (std::uint32_t count = 0; count < 300; count += 7) {
    const std::uint32_t begin = count % 5;  // ranges that start inside a group of eight
    const std::uint32_t end = begin + count;
    std::vector<float> x(end + pbf::kCandidatePadding, INFINITY), y(x), z(x);
    for (std::uint32_t k = begin; k < end; ++k) {
      x[k] = u(rng), y[k] = u(rng), z[k] = u(rng);
      if (k % 4 == 0) {  // on, or an ulp either side of, the sphere around a point of the box,
                         // outwards along x: where it touches the box's x faces, a boundary case
        const Eigen::Vector3f& p = inside[k / 4 % inside.size()];
        const float off[3] = {std::nextafter(radius, 0.0f), radius, std::nextafter(radius, 1.0f)};
        x[k] = p.x() == lo[0] ? p.x() - off[k % 3] : p.x() + off[k % 3], y[k] = p.y(), z[k] = p.z();
      }
    }
    std::vector<float> wx(count + 2 * pbf::kCandidatePadding), wy(wx), wz(wx), sx(wx), sy(wx), sz(wx);
    std::vector<std::uint32_t> wi(wx.size()), si(wx.size());
    const std::size_t n_wide = pbf::appendCandidatesNearBox(x.data(), y.data(), z.data(), begin, end, lo, hi, r2,
                                                            {wx.data(), wy.data(), wz.data(), wi.data()}, 0);
    const std::size_t n_scalar = pbf::appendCandidatesNearBoxScalar(x.data(), y.data(), z.data(), begin, end, lo, hi,
                                                                    r2, {sx.data(), sy.data(), sz.data(), si.data()}, 0);
    ASSERT_EQ(n_wide, n_scalar) << "count " << count << " (" << pbf::candidateFilterVariant() << ")";
    wi.resize(n_wide), si.resize(n_scalar);
    EXPECT_EQ(wi, si) << "count " << count;
    std::set<std::uint32_t> kept(si.begin(), si.end());
    EXPECT_TRUE(std::is_sorted(si.begin(), si.end()));
    for (std::size_t q = 0; q < n_scalar; ++q) {  // each kept point carries its own position
      EXPECT_EQ(sx[q], x[si[q]]);
      EXPECT_EQ(sy[q], y[si[q]]);
      EXPECT_EQ(sz[q], z[si[q]]);
    }
    for (std::uint32_t k = begin; k < end; ++k) {
      bool near = false;  // the neighbour search's own test, from any point in the box
      for (const Eigen::Vector3f& p : inside) {
        const float dx = x[k] - p.x(), dy = y[k] - p.y(), dz = z[k] - p.z();
        near = near || dx * dx + dy * dy + dz * dz < r2;
      }
      double gap2 = 0.0;  // the exact distance to the box
      for (float c : {x[k] - hi[0], lo[0] - x[k]}) gap2 += c > 0 ? double(c) * c : 0.0;
      for (float c : {y[k] - hi[1], lo[1] - y[k]}) gap2 += c > 0 ? double(c) * c : 0.0;
      for (float c : {z[k] - hi[2], lo[2] - z[k]}) gap2 += c > 0 ? double(c) * c : 0.0;
      if (near) {
        EXPECT_TRUE(kept.count(k)) << "point " << k << " near the box was dropped";
      }
      if (gap2 > 1.001 * r2) {
        EXPECT_FALSE(kept.count(k)) << "point " << k << " far from the box was kept";
      }
      near_total += near;
      dropped_total += !kept.count(k);
    }
  }
  EXPECT_GT(near_total, 200u);  // the test kept and dropped points
  EXPECT_GT(dropped_total, 200u);
}

// A NaN among a cell's points makes its box NaN: both builds then keep every point (dropping
// them would cost the cell's other particles their neighbours; the point test after it drops
// a NaN one).
TEST(CandidateFilter, GatheringNearANaNBoxKeepsEveryPoint) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<float> x = {0.0f, 5.0f, nan, -3.0f, 0.1f, INFINITY, INFINITY, INFINITY}, y(x.size(), 0.0f), z(y);
  const float lo[3] = {nan, 0.0f, 0.0f}, hi[3] = {nan, 0.0f, 0.0f};
  for (bool wide : {true, false}) {
    std::vector<float> ox(x.size() + 2 * pbf::kCandidatePadding), oy(ox), oz(ox);
    std::vector<std::uint32_t> oi(ox.size());
    const pbf::CandidateBuffer out{ox.data(), oy.data(), oz.data(), oi.data()};
    const std::size_t kept = wide ? pbf::appendCandidatesNearBox(x.data(), y.data(), z.data(), 0, 5, lo, hi, 0.01f, out, 0)
                                  : pbf::appendCandidatesNearBoxScalar(x.data(), y.data(), z.data(), 0, 5, lo, hi, 0.01f, out, 0);
    oi.resize(kept);
    EXPECT_EQ(oi, (std::vector<std::uint32_t>{0, 1, 2, 3, 4})) << (wide ? pbf::candidateFilterVariant() : "scalar");
  }
}

TEST(NeighborGrid, MortonInterleavesBits) {
  EXPECT_EQ(pbf::NeighborGrid::morton3(1, 0, 0), 1u);
  EXPECT_EQ(pbf::NeighborGrid::morton3(0, 1, 0), 2u);
  EXPECT_EQ(pbf::NeighborGrid::morton3(0, 0, 1), 4u);
  EXPECT_EQ(pbf::NeighborGrid::morton3(3, 3, 3), 63u);
}

}  // namespace
