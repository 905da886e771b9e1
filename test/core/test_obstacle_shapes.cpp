// Obstacle shapes: the cylinder's exact signed distance against a brute-force one, and a
// mesh obstacle answering through its signed distance grid in its pose.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "TestMeshes.h"
#include "pbf_ros/core/Obstacle.h"
#include "pbf_ros/core/Scene.h"

namespace {

pbf::Obstacle cylinder(float radius, float half_length, const Eigen::Isometry3f& pose) {
  pbf::Obstacle o;
  o.shape = pbf::Obstacle::Shape::Cylinder;
  o.radius = radius;
  o.half_length = half_length;
  o.pose = pose;
  return o;
}

Eigen::Isometry3f somePose() {
  return Eigen::Translation3f(0.3f, -0.2f, 0.5f) *
         Eigen::AngleAxisf(0.7f, Eigen::Vector3f(1.0f, 2.0f, -0.5f).normalized());
}

TEST(ObstacleCylinder, DistanceMatchesBruteForceOverItsSurface) {
  const float R = 0.06f, L = 0.1f;
  const pbf::Obstacle o = cylinder(R, L, somePose());
  // Dense samples of the local surface: side, both caps (the rim is on both).
  std::vector<Eigen::Vector3f> surface;
  const int na = 180, nz = 100, nr = 30;
  const float step = 2.0f * float(M_PI) * R / na;  // sample spacing, bounds the brute force's error
  for (int a = 0; a < na; ++a) {
    const float t = 2.0f * float(M_PI) * a / na, c = std::cos(t), s = std::sin(t);
    for (int k = 0; k <= nz; ++k) surface.emplace_back(R * c, R * s, -L + 2.0f * L * k / nz);
    for (int k = 0; k <= nr; ++k)
      for (float z : {-L, L}) surface.emplace_back(R * k / nr * c, R * k / nr * s, z);
  }
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  int inside = 0;
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3f q(u(rng) * 2.0f * R, u(rng) * 2.0f * R, u(rng) * 1.6f * L);
    const Eigen::Vector3f p = o.pose * q;
    Eigen::Vector3f n;
    const float d = o.signedDistance(p, n);
    float brute = INFINITY;
    for (const auto& s : surface) brute = std::min(brute, (q - s).norm());
    const bool in = std::hypot(q.x(), q.y()) < R && std::abs(q.z()) < L;
    inside += in;
    ASSERT_EQ(d < 0.0f, in) << q.transpose();
    ASSERT_NEAR(std::abs(d), brute, step) << q.transpose();
    ASSERT_NEAR(n.norm(), 1.0f, 1e-5f);
    // The closest point, p - d n, lies on the surface (exactly, not to the sampling).
    const Eigen::Vector3f c = o.pose.inverse() * Eigen::Vector3f(p - d * n);
    const float r = std::hypot(c.x(), c.y());
    const bool on_side = std::abs(r - R) < 1e-5f && std::abs(c.z()) <= L + 1e-5f;
    const bool on_cap = std::abs(std::abs(c.z()) - L) < 1e-5f && r <= R + 1e-5f;
    ASSERT_TRUE(on_side || on_cap) << "q " << q.transpose() << " closest " << c.transpose();
  }
  EXPECT_GT(inside, 100);  // the sampling did test the inside
}

TEST(ObstacleCylinder, BoundingRadiusAndValidation) {
  pbf::Obstacle o = cylinder(0.03f, 0.04f, Eigen::Isometry3f::Identity());
  EXPECT_FLOAT_EQ(o.boundingRadius(), 0.05f);  // the rim is the farthest point
  EXPECT_EQ(o.validate(), "");
  o.half_length = 0.0f;
  EXPECT_NE(o.validate().find("cylinder half_length"), std::string::npos);
  o.half_length = 0.04f;
  o.radius = NAN;
  EXPECT_NE(o.validate().find("radius"), std::string::npos);
}

TEST(ObstacleCylinder, SceneYamlReadsACylinderLikeACapsule) {
  const pbf::Scene s = pbf::loadSceneString(
      "container: {min: [0,0,0], max: [1,1,1]}\n"
      "fluid: [{box: {min: [0,0,0], max: [1,1,0.2]}}]\n"
      "obstacles: [{cylinder: {center: [0.5,0.5,0.6], radius: 0.1, half_length: 0.2, rpy: [1.5707963,0,0]},"
      " frame: pillar}]\n",
      "cyl.yaml");
  ASSERT_EQ(s.obstacles.size(), 1u);
  const pbf::Obstacle& o = s.obstacles[0];
  EXPECT_EQ(o.shape, pbf::Obstacle::Shape::Cylinder);
  EXPECT_FLOAT_EQ(o.radius, 0.1f);
  EXPECT_FLOAT_EQ(o.half_length, 0.2f);
  EXPECT_EQ(o.frame, "pillar");
  Eigen::Vector3f n;  // rolled a quarter turn: its axis lies along y
  EXPECT_NEAR(o.signedDistance(Eigen::Vector3f(0.5f, 0.75f, 0.6f), n), 0.05f, 1e-5f);
  EXPECT_NEAR(n.y(), 1.0f, 1e-5f);
  try {
    pbf::loadSceneString("container: {min: [0,0,0], max: [1,1,1]}\nfluid: [{box: {min: [0,0,0], max: [1,1,0.2]}}]\n"
                         "obstacles: [{cylinder: {center: [0.5,0.5,0.6], radius: 0.1}}]\n",
                         "cyl.yaml");
    FAIL() << "a cylinder without half_length loaded";
  } catch (const pbf::SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("obstacles[0].cylinder.half_length"), std::string::npos) << e.what();
  }
}

TEST(ObstacleMesh, AnswersThroughItsGridInItsPoseAndSharesItWithCopies) {
  pbf::SignedDistanceGridOptions opt;
  opt.cell = 0.005f;
  opt.band = 0.03f;
  const Eigen::Vector3f half(0.1f, 0.05f, 0.04f);
  pbf::Obstacle mesh;
  mesh.shape = pbf::Obstacle::Shape::Mesh;
  mesh.sdf = pbf::SignedDistanceGrid::build(pbf_test::boxMesh(half), opt);
  mesh.pose = somePose();
  EXPECT_EQ(mesh.validate(), "");
  pbf::Obstacle box;
  box.shape = pbf::Obstacle::Shape::Box;
  box.half_extents = half;
  box.pose = mesh.pose;
  EXPECT_NEAR(mesh.boundingRadius(), box.boundingRadius(), 1e-6f);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (int i = 0; i < 500; ++i) {
    // Off the box's edges and medial planes (there the interpolation rounds the kink),
    // within the band: the mesh obstacle must agree with the exact box.
    const Eigen::Vector3f q(u(rng) * 0.06f, u(rng) * 0.02f, (u(rng) > 0 ? 1 : -1) * (0.04f + u(rng) * 0.015f));
    const Eigen::Vector3f p = mesh.pose * q;
    Eigen::Vector3f nm, nb;
    const float dm = mesh.signedDistance(p, nm), db = box.signedDistance(p, nb);
    ASSERT_NEAR(dm, db, 1e-4f) << q.transpose();
    ASSERT_GT(nm.dot(nb), 0.9999f) << q.transpose();
  }
  const pbf::Obstacle copy = mesh;
  EXPECT_EQ(copy.sdf.get(), mesh.sdf.get());  // shared, not copied
  mesh.sdf.reset();
  EXPECT_NE(mesh.validate().find("no signed distance grid"), std::string::npos);
}

}  // namespace
