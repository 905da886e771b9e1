// SignedDistanceGrid: meshed solids against their exact distances, inside/outside on a
// non-convex cup and on a mesh with a hole, and clear errors for meshes that bound nothing.

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "TestMeshes.h"
#include "pbf_ros/core/Obstacle.h"
#include "pbf_ros/core/SignedDistanceGrid.h"

namespace {

constexpr float kCell = 0.005f;  // as for a particle spacing of 0.01 m
constexpr float kBand = 0.03f;   // h = 0.02 m plus one particle spacing

pbf::SignedDistanceGridOptions options() {
  pbf::SignedDistanceGridOptions o;
  o.cell = kCell;
  o.band = kBand;
  return o;
}

// Exact signed distance of the unmeshed box (Obstacle's analytic one).
float boxDistance(const Eigen::Vector3f& half, const Eigen::Isometry3f& pose, const Eigen::Vector3f& p,
                  Eigen::Vector3f& n) {
  pbf::Obstacle b;
  b.shape = pbf::Obstacle::Shape::Box;
  b.half_extents = half;
  b.pose = pose;
  return b.signedDistance(p, n);
}

struct Errors {
  double max = 0.0, sum2 = 0.0;
  int count = 0;
  void add(double e) {
    max = std::max(max, std::abs(e));
    sum2 += e * e;
    ++count;
  }
  double rms() const { return std::sqrt(sum2 / std::max(count, 1)); }
};

TEST(SignedDistanceGrid, RotatedBoxMatchesTheExactDistanceWithinAFractionOfACell) {
  const Eigen::Vector3f half(0.08f, 0.05f, 0.03f);
  const Eigen::Isometry3f pose(Eigen::AngleAxisf(0.5f, Eigen::Vector3f(1.0f, 1.0f, 0.3f).normalized()));
  const auto grid = pbf::SignedDistanceGrid::build(pbf_test::boxMesh(half, pose), options());
  EXPECT_EQ(grid->ambiguousNodes(), 0u);
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  Errors err;
  int wrong_sign = 0, tested_sign = 0;
  const float reach = half.norm() + kBand;
  while (err.count < 20000) {
    const Eigen::Vector3f p = reach * Eigen::Vector3f(u(rng), u(rng), u(rng));
    Eigen::Vector3f n_exact, n_grid;
    const float exact = boxDistance(half, pose, p, n_exact);
    if (exact > kBand) continue;  // the band is what the fluid sees
    const float d = grid->signedDistance(p, n_grid);
    err.add(d - exact);
    if (std::abs(exact) > kCell) {
      ++tested_sign;
      wrong_sign += (d < 0.0f) != (exact < 0.0f);
    }
  }
  std::printf("rotated box, cell %.4f m: max error %.3f cells, RMS %.4f cells, %d/%d wrong signs, %zu bytes\n",
              kCell, err.max / kCell, err.rms() / kCell, wrong_sign, tested_sign, grid->memoryBytes());
  // Trilinear interpolation is exact where the distance is linear (next to a face); the
  // error lives at the box's edges and inner medial planes, where it rounds the kink.
  EXPECT_LT(err.max, 0.6 * kCell);
  EXPECT_LT(err.rms(), 0.05 * kCell);
  EXPECT_EQ(wrong_sign, 0);
}

TEST(SignedDistanceGrid, NormalIsTheFaceNormalNextToAFace) {
  const Eigen::Vector3f half(0.08f, 0.05f, 0.03f);
  const Eigen::Isometry3f pose(Eigen::AngleAxisf(-0.9f, Eigen::Vector3f(0.2f, 1.0f, 0.4f).normalized()));
  const auto grid = pbf::SignedDistanceGrid::build(pbf_test::boxMesh(half, pose), options());
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (int i = 0; i < 1000; ++i) {
    // In front of the +x face and just inside it, away from its edges.
    // Its medial planes and edges stay 3 cells away from every interpolation cell used.
    const Eigen::Vector3f local(half.x() + u(rng) * 0.01f, u(rng) * 0.02f, u(rng) * 0.005f);
    Eigen::Vector3f n_exact, n_grid;
    const float exact = boxDistance(half, pose, pose * local, n_exact);
    const float d = grid->signedDistance(pose * local, n_grid);
    ASSERT_NEAR(d, exact, 1e-3f * kCell) << local.transpose();
    ASSERT_GT(n_grid.dot(pose.linear() * Eigen::Vector3f::UnitX()), 0.99999f) << local.transpose();
  }
}

// Exact unsigned distance to a mesh, by trying every triangle (a reference, slow).
float bruteDistance(const pbf::TriangleMesh& m, const Eigen::Vector3f& p) {
  float best = INFINITY;
  for (const auto& t : m.triangles) {
    const Eigen::Vector3f a = m.vertices[t[0]], b = m.vertices[t[1]], c = m.vertices[t[2]];
    // Project onto the plane; inside the triangle the plane distance is the distance.
    const Eigen::Vector3f nrm = (b - a).cross(c - a).normalized();
    const Eigen::Vector3f q = p - nrm.dot(p - a) * nrm;
    const bool in = (b - a).cross(q - a).dot(nrm) >= 0 && (c - b).cross(q - b).dot(nrm) >= 0 &&
                    (a - c).cross(q - c).dot(nrm) >= 0;
    if (in) best = std::min(best, std::abs(nrm.dot(p - a)));
    for (auto [e0, e1] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}}) {
      const float s = std::clamp((p - e0).dot(e1 - e0) / (e1 - e0).squaredNorm(), 0.0f, 1.0f);
      best = std::min(best, (p - (e0 + s * (e1 - e0))).norm());
    }
  }
  return best;
}

TEST(SignedDistanceGrid, SphereMatchesTheMeshAndTheSphereItApproximates) {
  const float R = 0.05f;
  const pbf::TriangleMesh mesh = pbf_test::sphereMesh(R, 48);
  const auto grid = pbf::SignedDistanceGrid::build(mesh, options());
  EXPECT_EQ(grid->ambiguousNodes(), 0u);
  EXPECT_EQ(mesh.openEdges(), 0u);
  // How far the facets lie inside the true sphere (the sagitta of a 48-gon, both ways).
  const float facet_gap = R * (1.0f - std::cos(float(M_PI) / 48.0f) * std::cos(float(M_PI) / 48.0f));
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  Errors vs_mesh, vs_sphere;
  for (int i = 0; i < 3000; ++i) {
    const Eigen::Vector3f dir = Eigen::Vector3f(u(rng), u(rng), u(rng)).normalized();
    const float radius = R + u(rng) * kBand;  // within the band, both sides
    if (radius < 0.002f) continue;
    const Eigen::Vector3f p = radius * dir;
    Eigen::Vector3f n;
    const float d = grid->signedDistance(p, n);
    const float brute = bruteDistance(mesh, p);
    // The sign of the brute force, from the analytic sphere, is safe away from the facets.
    if (std::abs(radius - R) > 2.0f * facet_gap) vs_mesh.add(d - (radius < R ? -brute : brute));
    vs_sphere.add(d - (radius - R));
    ASSERT_GT(n.dot(dir), 0.98f) << p.transpose();
  }
  std::printf("sphere R %.3f m, cell %.4f m: vs mesh max %.3f RMS %.4f cells; vs sphere max %.3f cells "
              "(facet gap %.3f cells); %zu bytes\n",
              R, kCell, vs_mesh.max / kCell, vs_mesh.rms() / kCell, vs_sphere.max / kCell,
              facet_gap / kCell, grid->memoryBytes());
  EXPECT_LT(vs_mesh.max, 0.25 * kCell);
  EXPECT_LT(vs_mesh.rms(), 0.05 * kCell);
  EXPECT_LT(vs_sphere.max, facet_gap + 0.25 * kCell);
}

TEST(SignedDistanceGrid, CupIsSolidInItsWallsAndHollowInside) {
  // Outer radius 5 cm, 8 cm tall, walls and bottom 1.2 cm: non-convex, open at the top.
  const float R = 0.05f, H = 0.08f, w = 0.012f;
  const auto grid = pbf::SignedDistanceGrid::build(pbf_test::cupMesh(R, H, w, 64), options());
  EXPECT_EQ(grid->ambiguousNodes(), 0u);
  Eigen::Vector3f n;
  EXPECT_LT(grid->signedDistance({R - 0.5f * w, 0.0f, 0.5f * H}, n), -0.004f);  // in the wall
  EXPECT_LT(grid->signedDistance({0.0f, 0.0f, 0.5f * w}, n), -0.004f);          // in the bottom
  // In the cavity, 2.8 cm above the bottom and 3.8 cm from the wall: the bottom is nearer.
  EXPECT_NEAR(grid->signedDistance({0.0f, 0.0f, 0.5f * H}, n), 0.5f * H - w, 1e-3f * kCell);
  EXPECT_NEAR(grid->signedDistance({0.0f, 0.0f, w + 0.01f}, n), 0.01f, 1e-3f * kCell);  // above the bottom
  EXPECT_GT(n.z(), 0.9999f);                                                       // ... which faces up
  EXPECT_NEAR(grid->signedDistance({0.0f, 0.0f, -0.01f}, n), 0.01f, 1e-3f * kCell);  // under it
  EXPECT_LT(n.z(), -0.9999f);
  // Everywhere: the sign agrees with the solid's own membership test, a cell from the surface.
  std::mt19937 rng(6);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  int inside = 0, checked = 0;
  for (int i = 0; i < 20000; ++i) {
    const Eigen::Vector3f p(u(rng) * 0.07f, u(rng) * 0.07f, 0.04f + u(rng) * 0.06f);
    const float r = std::hypot(p.x(), p.y());
    const bool in_wall = r < R && r > R - w && p.z() > 0.0f && p.z() < H;
    const bool in_bottom = r < R && p.z() > 0.0f && p.z() < w;
    const float to_surface = std::min({std::abs(r - R), std::abs(r - (R - w)), std::abs(p.z()),
                                       std::abs(p.z() - w), std::abs(p.z() - H)});
    if (to_surface < kCell) continue;  // on a (faceted) surface: either sign is fair
    ++checked;
    inside += in_wall || in_bottom;
    ASSERT_EQ(grid->signedDistance(p, n) < 0.0f, in_wall || in_bottom) << p.transpose();
  }
  EXPECT_GT(inside, 200);  // the thin walls were tested too
  EXPECT_GT(checked, 10000);
}

TEST(SignedDistanceGrid, AMissingFaceIsOutvotedByTheOtherTwoRays) {
  const Eigen::Vector3f half(0.04f, 0.04f, 0.04f);
  pbf::TriangleMesh open_box = pbf_test::boxMesh(half);
  open_box.triangles.erase(open_box.triangles.begin() + 2, open_box.triangles.begin() + 4);  // no +z face
  EXPECT_EQ(open_box.openEdges(), 4u);
  EXPECT_EQ(open_box.validate(), "");  // still bounds a volume: usable, with the vote
  const auto grid = pbf::SignedDistanceGrid::build(open_box, options());
  EXPECT_GT(grid->ambiguousNodes(), 0u);  // the z rays through the hole disagree ...
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (int i = 0; i < 5000; ++i) {  // ... but lose: inside and outside stay right
    const Eigen::Vector3f p = 0.07f * Eigen::Vector3f(u(rng), u(rng), u(rng));
    Eigen::Vector3f n;
    const float exact = boxDistance(half, Eigen::Isometry3f::Identity(), p, n);
    if (std::abs(exact) < kCell || (std::abs(p.x()) < half.x() + 2 * kCell &&
                                     std::abs(p.y()) < half.y() + 2 * kCell && p.z() > half.z() - 2 * kCell))
      continue;  // near the surface, or where the missing face would be
    ASSERT_EQ(grid->signedDistance(p, n) < 0.0f, exact < 0.0f) << p.transpose();
  }
}

TEST(SignedDistanceGrid, CoversTheMeshPlusTheBandAndReportsItsMemory) {
  const Eigen::Vector3f half(0.1f, 0.05f, 0.02f);
  const auto grid = pbf::SignedDistanceGrid::build(pbf_test::boxMesh(half), options());
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(grid->origin()[a], -half[a] - kBand, 1e-6f);
    EXPECT_GE((grid->nodes()[a] - 1) * kCell, 2.0f * (half[a] + kBand) - 1e-6f);
    EXPECT_LT((grid->nodes()[a] - 2) * kCell, 2.0f * (half[a] + kBand));
  }
  const std::size_t nodes = std::size_t(grid->nodes().prod());
  EXPECT_GE(grid->memoryBytes(), nodes * sizeof(float));
  EXPECT_LT(grid->memoryBytes(), nodes * sizeof(float) + 4096);
  Eigen::Vector3f n;  // beyond the grid: still a distance, at least the band
  EXPECT_GE(grid->signedDistance({1.0f, 0.0f, 0.0f}, n), kBand);
  EXPECT_NEAR(grid->signedDistance({1.0f, 0.0f, 0.0f}, n), 0.9f, 0.01f);
  EXPECT_NEAR(grid->boundingRadius(), half.norm(), 1e-6f);
}

std::string buildError(const pbf::TriangleMesh& mesh, pbf::SignedDistanceGridOptions opt = options()) {
  try {
    pbf::SignedDistanceGrid::build(mesh, opt);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(SignedDistanceGrid, DegenerateMeshesAreRefusedWithWhatIsWrong) {
  const pbf::TriangleMesh box = pbf_test::boxMesh(Eigen::Vector3f::Constant(0.02f));
  EXPECT_EQ(box.validate(), "");
  EXPECT_EQ(buildError(pbf::TriangleMesh{}), "mesh has no triangles");
  pbf::TriangleMesh nan = box;
  nan.vertices[3].y() = NAN;
  EXPECT_NE(nan.validate().find("mesh vertex 3 is not finite"), std::string::npos) << nan.validate();
  EXPECT_EQ(buildError(nan), nan.validate());
  pbf::TriangleMesh out_of_range = box;
  out_of_range.triangles[5] = Eigen::Vector3i(0, 1, 8);
  EXPECT_NE(buildError(out_of_range).find("triangle 5 uses vertex indices"), std::string::npos);
  pbf::TriangleMesh flat = box;  // every vertex squashed onto z = 0
  for (auto& v : flat.vertices) v.z() = 0.0f;
  EXPECT_NE(buildError(flat).find("encloses no volume"), std::string::npos) << buildError(flat);
  pbf::TriangleMesh one_sheet;  // a single square: no volume either
  one_sheet.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0.01f}, {0, 1, 0.01f}};
  one_sheet.triangles = {{0, 1, 2}, {0, 2, 3}};
  EXPECT_NE(buildError(one_sheet).find("encloses no volume"), std::string::npos) << buildError(one_sheet);

  pbf::SignedDistanceGridOptions bad = options();
  bad.cell = 0.0f;
  EXPECT_NE(buildError(box, bad).find("SDF cell"), std::string::npos);
  bad = options();
  bad.max_bytes = 1000;
  EXPECT_NE(buildError(box, bad).find("use a larger cell"), std::string::npos) << buildError(box, bad);
  // More nodes on one axis than an int counts (a URDF mesh scaled by 1e9, or 1e30 on every
  // axis): refused by the same check, not "cannot create std::vector larger than max_size()".
  for (const Eigen::Vector3f& scale : {Eigen::Vector3f(1, 1, 1e9f), Eigen::Vector3f(1e30f, 1e30f, 1e30f)}) {
    pbf::TriangleMesh huge = box;
    for (auto& v : huge.vertices) v = v.cwiseProduct(scale);
    EXPECT_NE(buildError(huge).find("use a larger cell"), std::string::npos) << buildError(huge);
  }
}

}  // namespace
