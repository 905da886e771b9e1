// urdfSolids: a robot's collision geometry as obstacles attached to its links, and a clear
// message for each thing that cannot be used while the rest of the robot still takes part.

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <sstream>

#include "pbf_ros/ros/MeshResource.h"
#include "pbf_ros/ros/UrdfSolids.h"

namespace {

const std::string kSource = PBF_SOURCE_DIR;
const std::string kCupStl = "file://" + kSource + "/urdf/meshes/cup.stl";

std::string robot(const std::string& links) {
  return "<?xml version=\"1.0\"?>\n<robot name=\"testbot\">\n" + links + "</robot>\n";
}
std::string link(const std::string& name, const std::string& collisions) {
  return "<link name=\"" + name + "\">" + collisions + "</link>\n";
}
std::string collision(const std::string& geometry, const std::string& origin = "") {
  return "<collision>" + origin + "<geometry>" + geometry + "</geometry></collision>";
}
std::string meshGeometry(const std::string& uri, const std::string& scale = "1 1 1") {
  return "<mesh filename=\"" + uri + "\" scale=\"" + scale + "\"/>";
}

pbf_ros::UrdfSolidsOptions options() {
  pbf_ros::UrdfSolidsOptions o;
  o.sdf.cell = 0.005f;  // particle spacing 0.01 m
  o.sdf.band = 0.03f;
  return o;
}

std::string joined(const std::vector<std::string>& lines) {
  std::string all;
  for (const auto& l : lines) all += l + "\n";
  return all;
}

const pbf_ros::UrdfSolid* find(const pbf_ros::UrdfSolids& s, const std::string& link) {
  for (const auto& solid : s.solids)
    if (solid.link == link) return &solid;
  return nullptr;
}

TEST(UrdfSolids, PrimitivesBecomeObstaclesOnTheirLinkAtTheCollisionOrigin) {
  const std::string urdf = robot(
      link("base", collision("<box size=\"0.2 0.1 0.06\"/>", "<origin xyz=\"0.1 0 0.03\" rpy=\"0 0 1.5707963\"/>")) +
      link("ball", collision("<sphere radius=\"0.04\"/>")) +
      link("pole", collision("<cylinder radius=\"0.02\" length=\"0.3\"/>", "<origin xyz=\"0 0 0.15\"/>") +
                       collision("<sphere radius=\"0.03\"/>", "<origin xyz=\"0 0 0.3\"/>")) +
      link("no_collision", "") +
      "<joint name=\"a\" type=\"fixed\"><parent link=\"base\"/><child link=\"ball\"/></joint>"
      "<joint name=\"b\" type=\"fixed\"><parent link=\"base\"/><child link=\"pole\"/></joint>"
      "<joint name=\"c\" type=\"fixed\"><parent link=\"base\"/><child link=\"no_collision\"/></joint>");
  const pbf_ros::UrdfSolids s = pbf_ros::urdfSolids(urdf, options());
  EXPECT_EQ(s.problems.size(), 0u) << joined(s.problems);
  EXPECT_EQ(s.robot_name, "testbot");
  ASSERT_EQ(s.solids.size(), 4u);  // base, ball, pole x 2; the link without collision is no solid
  const auto* base = find(s, "base");
  ASSERT_TRUE(base);
  EXPECT_EQ(base->obstacle.shape, pbf::Obstacle::Shape::Box);
  EXPECT_TRUE(base->obstacle.half_extents.isApprox(Eigen::Vector3f(0.1f, 0.05f, 0.03f)));
  EXPECT_EQ(base->obstacle.frame, "base");
  EXPECT_TRUE(base->obstacle.offset.translation().isApprox(Eigen::Vector3f(0.1f, 0.0f, 0.03f)));
  // Turned a quarter about z: the box's long side lies along the link's y.
  Eigen::Vector3f n;
  EXPECT_NEAR(base->obstacle.signedDistance(Eigen::Vector3f(0.1f, 0.15f, 0.03f), n), 0.05f, 1e-5f);
  EXPECT_TRUE(base->obstacle.pose.isApprox(base->obstacle.offset));
  std::vector<const pbf_ros::UrdfSolid*> pole;
  for (const auto& solid : s.solids)
    if (solid.link == "pole") pole.push_back(&solid);
  ASSERT_EQ(pole.size(), 2u);
  EXPECT_EQ(pole[0]->obstacle.shape, pbf::Obstacle::Shape::Cylinder);
  EXPECT_FLOAT_EQ(pole[0]->obstacle.half_length, 0.15f);
  EXPECT_FLOAT_EQ(pole[0]->obstacle.radius, 0.02f);
  EXPECT_EQ(pole[0]->name, "pole/collision_0");
  EXPECT_EQ(pole[1]->name, "pole/collision_1");
  EXPECT_EQ(pole[1]->obstacle.shape, pbf::Obstacle::Shape::Sphere);
  EXPECT_EQ(s.obstacles().size(), 4u);
  EXPECT_EQ(s.sdfBytes(), 0u);
}

std::string threeLinks() {
  return robot(link("arm_1", collision("<sphere radius=\"0.04\"/>")) +
               link("arm_2", collision("<sphere radius=\"0.04\"/>")) +
               link("gripper", collision("<box size=\"0.1 0.1 0.1\"/>")) + link("empty", "") +
               "<joint name=\"a\" type=\"fixed\"><parent link=\"arm_1\"/><child link=\"arm_2\"/></joint>"
               "<joint name=\"b\" type=\"fixed\"><parent link=\"arm_2\"/><child link=\"gripper\"/></joint>"
               "<joint name=\"c\" type=\"fixed\"><parent link=\"gripper\"/><child link=\"empty\"/></joint>");
}

TEST(UrdfSolids, LinksAreSelectedByListOrRegex) {
  pbf_ros::UrdfSolidsOptions o = options();
  o.link_regex = "arm_.*";
  pbf_ros::UrdfSolids s = pbf_ros::urdfSolids(threeLinks(), o);
  EXPECT_EQ(s.problems.size(), 0u) << joined(s.problems);
  ASSERT_EQ(s.solids.size(), 2u);
  EXPECT_EQ(s.solids[0].link, "arm_1");
  EXPECT_EQ(s.solids[1].link, "arm_2");

  o.link_regex.clear();
  o.links = {"gripper", "elbow", "empty", "arm_2"};
  s = pbf_ros::urdfSolids(threeLinks(), o);
  ASSERT_EQ(s.solids.size(), 2u);  // gripper and arm_2 still take part
  EXPECT_EQ(s.solids[0].link, "gripper");
  EXPECT_EQ(s.solids[1].link, "arm_2");
  ASSERT_EQ(s.problems.size(), 2u) << joined(s.problems);
  EXPECT_EQ(s.problems[0], "link 'elbow' is not in the URDF of robot 'testbot'");
  EXPECT_EQ(s.problems[1], "link 'empty' has no collision geometry");

  o.links.clear();
  o.link_regex = "arm_[";
  s = pbf_ros::urdfSolids(threeLinks(), o);
  EXPECT_TRUE(s.solids.empty());
  ASSERT_EQ(s.problems.size(), 1u);
  EXPECT_NE(s.problems[0].find("link regex 'arm_[' is not a valid regular expression"), std::string::npos)
      << s.problems[0];
  o.link_regex = "leg_.*";
  s = pbf_ros::urdfSolids(threeLinks(), o);
  ASSERT_EQ(s.problems.size(), 1u);
  EXPECT_EQ(s.problems[0], "no link of robot 'testbot' has collision geometry and matches 'leg_.*'");
}

// A pattern with nested repetitions backtracks exponentially: std::regex ran for minutes on a
// 35-character link name (the node hung at start-up) and overflowed the stack on a 20 000-
// character one. The match's work is bounded now: the pattern is refused, naming the link,
// and the long name is matched.
TEST(UrdfSolids, ALinkRegexThatBacktracksWithoutEndIsRefusedByName) {
  const std::string slow_name = "shoulder_pan_upper_arm_elbow_wrist_";
  const std::string long_name(20000, 'a');
  const std::string ball = collision("<sphere radius=\"0.04\"/>");
  auto fixedJoint = [](const std::string& name, const std::string& child) {
    return "<joint name=\"" + name + "\" type=\"fixed\"><parent link=\"arm_link\"/><child link=\"" + child +
           "\"/></joint>";
  };
  const std::string urdf = robot(link("arm_link", ball) + link(slow_name, ball) + link(long_name, ball) +
                                 fixedJoint("a", slow_name) + fixedJoint("b", long_name));
  pbf_ros::UrdfSolidsOptions o = options();
  o.link_regex = "(\\w+_?)+_link";
  pbf_ros::UrdfSolids s = pbf_ros::urdfSolids(urdf, o);
  EXPECT_TRUE(s.solids.empty());
  ASSERT_EQ(s.problems.size(), 1u) << joined(s.problems);
  EXPECT_NE(s.problems[0].find("link regex '(\\w+_?)+_link' takes too long to match link '"), std::string::npos)
      << s.problems[0];

  o.link_regex = "(a|b)*";  // the very long name, which overflowed std::regex's stack, matches
  s = pbf_ros::urdfSolids(urdf, o);
  EXPECT_EQ(s.problems.size(), 0u) << joined(s.problems);
  ASSERT_EQ(s.solids.size(), 1u);
  EXPECT_EQ(s.solids[0].link, long_name);

  o.link_regex = "arm_.*";  // an ordinary pattern on the same robot
  s = pbf_ros::urdfSolids(urdf, o);
  EXPECT_EQ(s.problems.size(), 0u) << joined(s.problems);
  ASSERT_EQ(s.solids.size(), 1u);
  EXPECT_EQ(s.solids[0].link, "arm_link");
}

TEST(UrdfSolids, AnUnparsableUrdfSaysWhy) {
  pbf_ros::UrdfSolids s = pbf_ros::urdfSolids("<robot name=\"x\"><link name=\"a\">", options());
  EXPECT_TRUE(s.solids.empty());
  ASSERT_EQ(s.problems.size(), 1u);
  EXPECT_NE(s.problems[0].find("the robot description is not a valid URDF: "), std::string::npos) << s.problems[0];
  s = pbf_ros::urdfSolids(robot(link("a", collision("<sphere radius=\"0.1\"/>")) + link("a", "")), options());
  ASSERT_EQ(s.problems.size(), 1u);
  EXPECT_NE(s.problems[0].find("not a valid URDF"), std::string::npos);
  EXPECT_NE(s.problems[0].find("'a'"), std::string::npos) << s.problems[0];  // the parser names the duplicate
}

TEST(UrdfSolids, AMeshLinkGetsAScaledSignedDistanceGridSharedWithItsTwins) {
  const std::string urdf = robot(
      link("cup", collision(meshGeometry(kCupStl, "2 2 2"), "<origin xyz=\"0 0 0.5\"/>")) +
      link("cup_twin", collision(meshGeometry(kCupStl, "2 2 2"))) +
      link("small_cup", collision(meshGeometry(kCupStl))) +
      "<joint name=\"a\" type=\"fixed\"><parent link=\"cup\"/><child link=\"cup_twin\"/></joint>"
      "<joint name=\"b\" type=\"fixed\"><parent link=\"cup\"/><child link=\"small_cup\"/></joint>");
  const pbf_ros::UrdfSolids s = pbf_ros::urdfSolids(urdf, options());
  EXPECT_EQ(s.problems.size(), 0u) << joined(s.problems);
  ASSERT_EQ(s.solids.size(), 3u);
  const auto *cup = find(s, "cup"), *twin = find(s, "cup_twin"), *small = find(s, "small_cup");
  ASSERT_TRUE(cup && twin && small);
  EXPECT_EQ(cup->obstacle.shape, pbf::Obstacle::Shape::Mesh);
  EXPECT_EQ(cup->geometry, "mesh '" + kCupStl + "'");
  EXPECT_EQ(cup->obstacle.sdf.get(), twin->obstacle.sdf.get());  // same file and scale: one grid
  EXPECT_NE(cup->obstacle.sdf.get(), small->obstacle.sdf.get());
  EXPECT_EQ(s.sdfBytes(), cup->obstacle.sdf->memoryBytes() + small->obstacle.sdf->memoryBytes());
  // cup.stl: outer radius 5 cm, 9 cm tall, walls and bottom 1.2 cm; twice that here, and
  // placed 0.5 m up its link.
  const pbf::Obstacle& o = cup->obstacle;
  EXPECT_EQ(o.sdf->mesh().openEdges(), 0u);  // read as one closed surface
  EXPECT_NEAR(o.boundingRadius(), std::hypot(0.1f, 0.18f), 1e-4f);
  Eigen::Vector3f n;
  EXPECT_LT(o.signedDistance(Eigen::Vector3f(0.1f - 0.012f, 0.0f, 0.5f + 0.09f), n), -0.008f);  // in the wall
  EXPECT_NEAR(o.signedDistance(Eigen::Vector3f(0.0f, 0.0f, 0.5f + 0.024f + 0.03f), n), 0.03f, 1e-4f);
  EXPECT_GT(n.z(), 0.999f);  // the cavity's floor faces up
  EXPECT_NEAR(o.signedDistance(Eigen::Vector3f(0.0f, 0.0f, 0.5f - 0.02f), n), 0.02f, 1e-4f);
  EXPECT_LT(n.z(), -0.999f);
}

// Each grid is bounded, but a robot of many large meshes (each scale its own grid) could
// ask for more memory than the machine has: the grids share one budget, and a mesh whose
// grid does not fit in what is left is refused by name while the others take part.
TEST(UrdfSolids, MeshGridsShareOneMemoryBudget) {
  pbf_ros::UrdfSolidsOptions o = options();
  const std::size_t one =
      pbf_ros::urdfSolids(robot(link("cup", collision(meshGeometry(kCupStl, "2 2 2")))), o).sdfBytes();
  ASSERT_GT(one, 0u);
  o.max_mesh_grid_bytes = one * 5 / 2;  // room for two such grids, not three
  const std::string urdf = robot(
      link("cup_a", collision(meshGeometry(kCupStl, "2 2 2"))) +
      link("cup_b", collision(meshGeometry(kCupStl, "2.01 2.01 2.01"))) +
      link("cup_c", collision(meshGeometry(kCupStl, "2.02 2.02 2.02"))) +
      link("cup_d", collision(meshGeometry(kCupStl, "2 2 2"))) +  // cup_a's grid: no more memory
      "<joint name=\"a\" type=\"fixed\"><parent link=\"cup_a\"/><child link=\"cup_b\"/></joint>"
      "<joint name=\"b\" type=\"fixed\"><parent link=\"cup_a\"/><child link=\"cup_c\"/></joint>"
      "<joint name=\"c\" type=\"fixed\"><parent link=\"cup_a\"/><child link=\"cup_d\"/></joint>");
  const pbf_ros::UrdfSolids s = pbf_ros::urdfSolids(urdf, o);
  std::printf("%s", joined(s.problems).c_str());
  ASSERT_EQ(s.solids.size(), 3u) << joined(s.problems);
  EXPECT_EQ(s.solids[0].link, "cup_a");
  EXPECT_EQ(s.solids[1].link, "cup_b");
  EXPECT_EQ(s.solids[2].link, "cup_d");
  EXPECT_LE(s.sdfBytes(), o.max_mesh_grid_bytes);
  ASSERT_EQ(s.problems.size(), 1u) << joined(s.problems);
  EXPECT_NE(s.problems[0].find("link 'cup_c'"), std::string::npos) << s.problems[0];
  EXPECT_NE(s.problems[0].find("the robot's mesh grids may take"), std::string::npos) << s.problems[0];
}

// A mesh narrower than the grid's cell (half the particle spacing) is a point to the fluid.
// It takes part, as before, but a wrong <mesh scale> is named instead of passing in silence.
TEST(UrdfSolids, AMeshSmallerThanTheGridCellIsNamedWithItsScale) {
  const std::string urdf = robot(link("cup", collision(meshGeometry(kCupStl))) +
                                 link("speck", collision(meshGeometry(kCupStl, "0.001 0.001 0.001"))) +
                                 "<joint name=\"a\" type=\"fixed\"><parent link=\"cup\"/>"
                                 "<child link=\"speck\"/></joint>");
  const pbf_ros::UrdfSolids s = pbf_ros::urdfSolids(urdf, options());
  ASSERT_EQ(s.solids.size(), 2u) << joined(s.problems);
  ASSERT_EQ(s.problems.size(), 1u) << joined(s.problems);
  const std::string& p = s.problems[0];
  EXPECT_NE(p.find("link 'speck' collision 0"), std::string::npos) << p;
  EXPECT_NE(p.find("0.0001 m across at scale [0.001, 0.001, 0.001]"), std::string::npos) << p;
  EXPECT_NE(p.find("grid cell of 0.005 m"), std::string::npos) << p;
  EXPECT_NE(p.find("it takes part"), std::string::npos) << p;
}

TEST(UrdfSolids, AColladaMeshIsReadLikeAnStl) {
  // DAE through the same reader (geometric_shapes -> assimp): a closed 10 x 6 x 4 cm box.
  const std::string dae = "file://" + kSource + "/test/data/unit_box.dae";
  const pbf_ros::UrdfSolids s = pbf_ros::urdfSolids(
      robot(link("block", collision(meshGeometry(dae), "<origin xyz=\"0 0 0.1\"/>"))), options());
  EXPECT_EQ(s.problems.size(), 0u) << joined(s.problems);
  ASSERT_EQ(s.solids.size(), 1u);
  const pbf::Obstacle& o = s.solids[0].obstacle;
  ASSERT_EQ(o.shape, pbf::Obstacle::Shape::Mesh);
  EXPECT_EQ(o.sdf->mesh().triangles.size(), 12u);
  EXPECT_EQ(o.sdf->mesh().openEdges(), 0u);
  EXPECT_NEAR(std::abs(o.sdf->mesh().signedVolume()), 0.1 * 0.06 * 0.04, 1e-8);
  Eigen::Vector3f n;  // in the link frame: the box sits 0.1 m up, its top face 2 cm above that
  EXPECT_NEAR(o.signedDistance(Eigen::Vector3f(0.0f, 0.0f, 0.1f + 0.02f + 0.01f), n), 0.01f, 1e-4f);
  EXPECT_GT(n.z(), 0.999f);
  EXPECT_NEAR(o.signedDistance(Eigen::Vector3f(0.0f, 0.0f, 0.1f), n), -0.02f, 0.5f * 0.005f);
}

TEST(UrdfSolids, AMissingOrDegenerateMeshIsReportedAndTheRestStays) {
  const std::string flat = "file://" + kSource + "/test/data/flat_square.stl";
  const std::string urdf = robot(
      link("base", collision("<box size=\"0.1 0.1 0.1\"/>")) +
      link("lost", collision(meshGeometry("file:///nonexistent/lost.stl"))) +
      link("flat", collision(meshGeometry(flat))) +
      link("nowhere", collision(meshGeometry("package://no_such_package_xyz/m.stl"))) +
      link("zero", collision("<sphere radius=\"0\"/>")) +
      "<joint name=\"a\" type=\"fixed\"><parent link=\"base\"/><child link=\"lost\"/></joint>"
      "<joint name=\"b\" type=\"fixed\"><parent link=\"base\"/><child link=\"flat\"/></joint>"
      "<joint name=\"c\" type=\"fixed\"><parent link=\"base\"/><child link=\"nowhere\"/></joint>"
      "<joint name=\"d\" type=\"fixed\"><parent link=\"base\"/><child link=\"zero\"/></joint>");
  const pbf_ros::UrdfSolids s = pbf_ros::urdfSolids(urdf, options());
  ASSERT_EQ(s.solids.size(), 1u);
  EXPECT_EQ(s.solids[0].link, "base");
  const std::string all = joined(s.problems);
  std::printf("%s", all.c_str());
  ASSERT_EQ(s.problems.size(), 4u) << all;
  // In link name order: flat, lost, nowhere, zero.
  EXPECT_NE(s.problems[0].find("link 'flat' collision 0 (mesh '" + flat +
                               "'): cannot bound a solid: mesh encloses no volume"),
            std::string::npos) << s.problems[0];
  EXPECT_NE(s.problems[1].find("link 'lost' collision 0 (mesh 'file:///nonexistent/lost.stl'): cannot read mesh"),
            std::string::npos) << s.problems[1];
  EXPECT_NE(s.problems[2].find("link 'nowhere'"), std::string::npos) << s.problems[2];
  EXPECT_NE(s.problems[2].find("no_such_package_xyz"), std::string::npos) << s.problems[2];
  EXPECT_NE(s.problems[3].find("link 'zero' collision 0 (sphere): radius must be finite and > 0"),
            std::string::npos) << s.problems[3];
  for (const auto& p : s.problems) EXPECT_NE(p.find("left out"), std::string::npos) << p;
}

// A mesh is read whole into memory before its triangles are counted: a file that never ends
// (/dev/zero) grew the node without bound, and a download could be of any size. Only local
// regular files up to kMaxMeshFileBytes are read; each refusal names the link and says why.
TEST(UrdfSolids, MeshFilesAreReadOnlyWhenLocalRegularAndSmall) {
  const std::string big = ::testing::TempDir() + "pbf_big_mesh.stl";
  {
    std::ofstream out(big, std::ios::binary);
    out.seekp(static_cast<std::streamoff>(40) << 20);  // 40 MiB, sparse: no disk used
    out.put('\0');
  }
  const std::string urdf = robot(
      link("base", collision("<box size=\"0.1 0.1 0.1\"/>")) +
      link("endless", collision(meshGeometry("file:///dev/zero"))) +
      link("huge", collision(meshGeometry("file://" + big))) +
      link("remote", collision(meshGeometry("http://localhost:9/arm.stl"))) +
      "<joint name=\"a\" type=\"fixed\"><parent link=\"base\"/><child link=\"endless\"/></joint>"
      "<joint name=\"b\" type=\"fixed\"><parent link=\"base\"/><child link=\"huge\"/></joint>"
      "<joint name=\"c\" type=\"fixed\"><parent link=\"base\"/><child link=\"remote\"/></joint>");
  const pbf_ros::UrdfSolids s = pbf_ros::urdfSolids(urdf, options());
  std::remove(big.c_str());
  ASSERT_EQ(s.solids.size(), 1u);
  EXPECT_EQ(s.solids[0].link, "base");
  ASSERT_EQ(s.problems.size(), 3u) << joined(s.problems);
  // In link name order: endless, huge, remote.
  EXPECT_NE(s.problems[0].find("link 'endless' collision 0 (mesh 'file:///dev/zero'): cannot read mesh "
                               "'file:///dev/zero': not a regular file"),
            std::string::npos) << s.problems[0];
  EXPECT_NE(s.problems[1].find("link 'huge'"), std::string::npos) << s.problems[1];
  EXPECT_NE(s.problems[1].find("40.0 MiB, more than the 32 MiB a collision mesh file may have"), std::string::npos)
      << s.problems[1];
  EXPECT_NE(s.problems[2].find("link 'remote'"), std::string::npos) << s.problems[2];
  EXPECT_NE(s.problems[2].find("only local meshes are read"), std::string::npos) << s.problems[2];
}

// A binary STL of `triangles` (each as three corners) at `path`.
void writeStl(const std::string& path, const std::vector<std::array<Eigen::Vector3f, 3>>& triangles) {
  std::ofstream out(path, std::ios::binary);
  const char header[80] = {};
  out.write(header, 80);
  const std::uint32_t count = static_cast<std::uint32_t>(triangles.size());
  out.write(reinterpret_cast<const char*>(&count), 4);
  for (const auto& t : triangles) {
    const float normal[3] = {0, 0, 0};
    out.write(reinterpret_cast<const char*>(normal), 12);
    for (const Eigen::Vector3f& v : t) out.write(reinterpret_cast<const char*>(v.data()), 12);
    const std::uint16_t attributes = 0;
    out.write(reinterpret_cast<const char*>(&attributes), 2);
  }
}

// The 12 triangles of a cube of half-size h, facing out.
std::vector<std::array<Eigen::Vector3f, 3>> cube(float h) {
  const Eigen::Vector3f v[8] = {{-h, -h, -h}, {h, -h, -h}, {h, h, -h}, {-h, h, -h},
                                {-h, -h, h},  {h, -h, h},  {h, h, h},  {-h, h, h}};
  const int f[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                        {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
  std::vector<std::array<Eigen::Vector3f, 3>> out;
  for (const auto& t : f) out.push_back({v[t[0]], v[t[1]], v[t[2]]});
  return out;
}

// Found by a probe of the running node (session 36): a NaN or infinite size made the URDF
// parser drop the element and say so only in its own log; a link with thousands of
// collision elements took part beyond a scene's obstacle limit; a visual-sized mesh held up
// every ~reset for 19 s while it was gridded; a mesh with a hole stirred a resting tank.
TEST(UrdfSolids, WhatTheParserDropsIsNamedAndMeshesAndCountsAreBounded) {
  // What the parser drops: named through its own message.
  pbf_ros::UrdfSolids s = pbf_ros::urdfSolids(
      robot(link("base", collision("<box size=\"0.1 0.1 0.1\"/>")) +
            link("box_nan", collision("<box size=\"nan 0.1 0.1\"/>")) +
            "<joint name=\"j\" type=\"fixed\"><parent link=\"base\"/><child link=\"box_nan\"/></joint>"),
      options());
  EXPECT_EQ(s.solids.size(), 1u);
  const std::string dropped = joined(s.problems);
  EXPECT_NE(dropped.find("the URDF parser left out what it could not read"), std::string::npos) << dropped;
  EXPECT_NE(dropped.find("box_nan"), std::string::npos) << dropped;

  // More collision elements than a scene may have obstacles: the first 256 take part.
  std::string spheres;
  for (int i = 0; i < 300; ++i) spheres += collision("<sphere radius=\"0.01\"/>");
  s = pbf_ros::urdfSolids(robot(link("many", spheres)), options());
  EXPECT_EQ(s.solids.size(), pbf::kMaxObstacles);
  ASSERT_EQ(s.problems.size(), 1u) << joined(s.problems);
  EXPECT_NE(s.problems[0].find("at most 256 solids take part"), std::string::npos) << s.problems[0];
  EXPECT_NE(s.problems[0].find("the 44 collision elements after them, from link 'many' collision 256 on"),
            std::string::npos) << s.problems[0];

  // A mesh with a hole takes part, named; one with more triangles than a collision mesh
  // needs is refused before it is gridded.
  const std::string dir = testing::TempDir();
  std::vector<std::array<Eigen::Vector3f, 3>> open_box = cube(0.05f);
  open_box.resize(10);  // the top face's two triangles missing
  writeStl(dir + "/open_box.stl", open_box);
  std::vector<std::array<Eigen::Vector3f, 3>> fine;
  while (fine.size() <= pbf_ros::kMaxMeshTriangles) {  // cubes side by side: 12 triangles each
    const Eigen::Vector3f at(0.01f * float(fine.size() / 12 % 100), 0.01f * float(fine.size() / 1200), 0.0f);
    for (auto t : cube(0.004f)) {
      for (auto& v : t) v += at;
      fine.push_back(t);
    }
  }
  writeStl(dir + "/fine.stl", fine);
  s = pbf_ros::urdfSolids(
      robot(link("holed", collision(meshGeometry("file://" + dir + "/open_box.stl"))) +
            link("visual", collision(meshGeometry("file://" + dir + "/fine.stl"))) +
            "<joint name=\"j\" type=\"fixed\"><parent link=\"holed\"/><child link=\"visual\"/></joint>"),
      options());
  ASSERT_EQ(s.solids.size(), 1u) << joined(s.problems);
  EXPECT_EQ(s.solids[0].link, "holed");
  ASSERT_EQ(s.problems.size(), 2u) << joined(s.problems);
  EXPECT_NE(s.problems[0].find("link 'holed' collision 0"), std::string::npos) << s.problems[0];
  EXPECT_NE(s.problems[0].find("not closed (4 open edges)"), std::string::npos) << s.problems[0];
  EXPECT_NE(s.problems[0].find("it takes part"), std::string::npos) << s.problems[0];
  EXPECT_NE(s.problems[1].find("link 'visual' collision 0"), std::string::npos) << s.problems[1];
  EXPECT_NE(s.problems[1].find("more than the 50000 a collision mesh may have"), std::string::npos)
      << s.problems[1];
}

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(UrdfSolids, TheDemoArmLoadsWithEveryLinkAsASolid) {
  // Resolve package://pbf_ros/ to this source tree without relying on ROS_PACKAGE_PATH.
  const std::string urdf = std::regex_replace(readFile(kSource + "/urdf/pouring_arm.urdf"),
                                              std::regex("package://pbf_ros/"), "file://" + kSource + "/");
  ASSERT_FALSE(urdf.empty());
  const pbf_ros::UrdfSolids s = pbf_ros::urdfSolids(urdf, options());
  EXPECT_EQ(s.problems.size(), 0u) << joined(s.problems);
  EXPECT_EQ(s.robot_name, "pouring_arm");
  ASSERT_EQ(s.solids.size(), 6u);  // base: disc and post; upper arm; forearm; cup: stem and cup
  for (const auto& solid : s.solids) {
    EXPECT_EQ(solid.obstacle.validate(), "") << solid.name;
    if (!solid.obstacle.sdf) continue;
    const auto& g = *solid.obstacle.sdf;
    EXPECT_EQ(g.mesh().openEdges(), 0u) << solid.name;
    EXPECT_EQ(g.ambiguousNodes(), 0u) << solid.name;
    std::printf("%-10s %-44s %4zu triangles, grid %3d x %3d x %3d, %7zu bytes\n", solid.link.c_str(),
                solid.geometry.c_str(), g.mesh().triangles.size(), g.nodes().x(), g.nodes().y(), g.nodes().z(),
                g.memoryBytes());
  }
  std::printf("all mesh grids: %zu bytes (cell %.4f m, band %.3f m)\n", s.sdfBytes(), options().sdf.cell,
              options().sdf.band);
  const pbf_ros::UrdfSolid* cup = nullptr;  // the cup link's mesh (beside its stem)
  for (const auto& solid : s.solids)
    if (solid.link == "cup" && solid.obstacle.shape == pbf::Obstacle::Shape::Mesh) cup = &solid;
  ASSERT_TRUE(cup);
  // The cup stands on a 3 cm stem: its mesh's origin is 3 cm up the link's z axis.
  EXPECT_NEAR(cup->obstacle.pose.translation().z(), 0.03f, 1e-6f);
  Eigen::Vector3f n;  // water stands in the cup: its cavity is outside the solid
  EXPECT_NEAR(cup->obstacle.signedDistance(Eigen::Vector3f(0.0f, 0.0f, 0.08f), n), 0.038f, 1e-3f);
  // Mid-wall (1.2 cm thick) is its medial surface, where interpolation rounds the kink.
  EXPECT_LT(cup->obstacle.signedDistance(Eigen::Vector3f(0.044f, 0.0f, 0.08f), n), -0.006f + 0.5f * 0.005f);
}

TEST(UrdfSolids, PackageUrisResolveThroughTheRosPackagePath) {
  // The node reads package:// URIs; rospack finds this source tree by its package.xml.
  setenv("ROS_PACKAGE_PATH", kSource.c_str(), 1);
  pbf::TriangleMesh mesh;
  std::string error;
  ASSERT_TRUE(pbf_ros::loadMeshResource("package://pbf_ros/urdf/meshes/forearm.stl", Eigen::Vector3d::Ones(),
                                        mesh, error))
      << error;
  EXPECT_EQ(mesh.triangles.size(), 32u);
  EXPECT_EQ(mesh.validate(), "");
}

}  // namespace
