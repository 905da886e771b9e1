// makeSceneMarkers: container and obstacles, in the frames the solver moves them with.
#include <gtest/gtest.h>

#include "pbf_ros/ros/SceneMarkers.h"

using visualization_msgs::Marker;

namespace {
pbf::Scene sceneWithObstacles() {
  pbf::Scene scene;
  scene.container = Eigen::AlignedBox3f(Eigen::Vector3f::Zero(), Eigen::Vector3f(1.0f, 0.5f, 0.8f));
  pbf::Obstacle box;
  box.shape = pbf::Obstacle::Shape::Box;
  box.half_extents = Eigen::Vector3f(0.1f, 0.2f, 0.3f);
  box.pose = Eigen::Isometry3f(Eigen::Translation3f(0.5f, 0.25f, 0.1f));
  pbf::Obstacle capsule;
  capsule.shape = pbf::Obstacle::Shape::Capsule;
  capsule.frame = "cup";
  capsule.offset = Eigen::Isometry3f(Eigen::Translation3f(0.2f, 0.2f, 0.2f));
  scene.obstacles = {box, capsule};
  return scene;
}
}  // namespace

TEST(SceneMarkers, StartsWithDeleteAllThenTheContainer) {
  const auto array = pbf_ros::makeSceneMarkers(sceneWithObstacles(), "fluid_domain", ros::Time());
  ASSERT_GE(array.markers.size(), 3u);
  EXPECT_EQ(array.markers[0].action, Marker::DELETEALL);
  EXPECT_EQ(array.markers[1].ns, "container");
  EXPECT_EQ(array.markers[1].type, Marker::LINE_LIST);
  EXPECT_EQ(array.markers[1].points.size(), 24u);  // 12 edges
  EXPECT_EQ(array.markers[1].header.frame_id, "fluid_domain");
}

TEST(SceneMarkers, ObstaclesHaveTheirShapeSizeAndFrame) {
  const auto array = pbf_ros::makeSceneMarkers(sceneWithObstacles(), "fluid_domain", ros::Time());
  std::vector<Marker> obstacles;
  for (const auto& m : array.markers)
    if (m.ns == "obstacles") obstacles.push_back(m);
  ASSERT_EQ(obstacles.size(), 4u);  // box + capsule (cylinder and two end spheres)
  EXPECT_EQ(obstacles[0].type, Marker::CUBE);
  EXPECT_FLOAT_EQ(obstacles[0].scale.y, 0.4f);
  EXPECT_FLOAT_EQ(obstacles[0].pose.position.x, 0.5f);
  EXPECT_EQ(obstacles[0].header.frame_id, "fluid_domain");
  EXPECT_EQ(obstacles[1].type, Marker::CYLINDER);
  EXPECT_EQ(obstacles[1].header.frame_id, "cup");  // attached: drawn in its frame
  EXPECT_TRUE(obstacles[1].frame_locked);          // ... and follows it
  EXPECT_FLOAT_EQ(obstacles[1].pose.position.x, 0.2f);
  EXPECT_EQ(obstacles[2].type, Marker::SPHERE);
  for (std::size_t i = 0; i < obstacles.size(); ++i)
    for (std::size_t j = i + 1; j < obstacles.size(); ++j) EXPECT_NE(obstacles[i].id, obstacles[j].id);
}

TEST(SceneMarkers, AttachedContainerIsDrawnInItsFrame) {
  pbf::Scene scene = sceneWithObstacles();
  scene.container_frame = "tank";
  const auto array = pbf_ros::makeSceneMarkers(scene, "fluid_domain", ros::Time());
  EXPECT_EQ(array.markers[1].header.frame_id, "tank");
}

TEST(SceneMarkers, CylindersAndMeshesLookLikeWhatTheSolverUses) {
  pbf::Scene scene = sceneWithObstacles();
  pbf::Obstacle cylinder;
  cylinder.shape = pbf::Obstacle::Shape::Cylinder;
  cylinder.radius = 0.03f;
  cylinder.half_length = 0.1f;
  pbf::TriangleMesh tetra;  // a tetrahedron: 4 triangles
  tetra.vertices = {{0, 0, 0}, {0.1f, 0, 0}, {0, 0.1f, 0}, {0, 0, 0.1f}};
  tetra.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  pbf::SignedDistanceGridOptions grid;
  grid.cell = 0.01f;
  grid.band = 0.02f;
  pbf::Obstacle mesh;
  mesh.shape = pbf::Obstacle::Shape::Mesh;
  mesh.sdf = pbf::SignedDistanceGrid::build(tetra, grid);
  mesh.frame = "gripper";
  scene.obstacles = {cylinder, mesh};
  const auto array = pbf_ros::makeSceneMarkers(scene, "fluid_domain", ros::Time());
  std::vector<Marker> obstacles;
  for (const auto& m : array.markers)
    if (m.ns == "obstacles") obstacles.push_back(m);
  ASSERT_EQ(obstacles.size(), 2u);
  EXPECT_EQ(obstacles[0].type, Marker::CYLINDER);
  EXPECT_FLOAT_EQ(obstacles[0].scale.x, 0.06f);
  EXPECT_FLOAT_EQ(obstacles[0].scale.z, 0.2f);
  EXPECT_EQ(obstacles[1].type, Marker::TRIANGLE_LIST);
  EXPECT_EQ(obstacles[1].header.frame_id, "gripper");
  ASSERT_EQ(obstacles[1].points.size(), 12u);
  EXPECT_FLOAT_EQ(obstacles[1].points[11].z, 0.1f);  // the last triangle's last vertex
  EXPECT_FLOAT_EQ(obstacles[1].scale.x, 1.0f);
}

TEST(SceneMarkers, EmittersAreArrowsInTheirFrameAndDrainsTheirRegion) {
  pbf::Scene scene;
  scene.container = Eigen::AlignedBox3f(Eigen::Vector3f::Zero(), Eigen::Vector3f::Ones());
  pbf::Emitter tap;
  tap.frame = "tap";
  tap.position = Eigen::Vector3f(0.1f, 0.2f, 0.3f);
  tap.direction = Eigen::Vector3f(0, 0, -1);
  tap.radius = 0.02f;
  tap.speed = 1.0f;
  scene.emitters.push_back(tap);
  pbf::Drain box;
  box.min = Eigen::Vector3f(0.0f, 0.0f, 0.0f);
  box.max = Eigen::Vector3f(0.2f, 0.1f, 0.05f);
  pbf::Drain ball;
  ball.shape = pbf::Drain::Shape::Sphere;
  ball.center = Eigen::Vector3f(0.5f, 0.5f, 0.0f);
  ball.radius = 0.03f;
  scene.drains = {box, ball};
  const auto array = pbf_ros::makeSceneMarkers(scene, "fluid_domain", ros::Time(1.0));
  std::vector<visualization_msgs::Marker> emitters, drains;
  for (const auto& m : array.markers) {
    if (m.ns == "emitters") emitters.push_back(m);
    if (m.ns == "drains") drains.push_back(m);
  }
  ASSERT_EQ(emitters.size(), 1u);
  EXPECT_EQ(emitters[0].header.frame_id, "tap");
  EXPECT_EQ(emitters[0].type, visualization_msgs::Marker::ARROW);
  ASSERT_EQ(emitters[0].points.size(), 2u);
  EXPECT_FLOAT_EQ(emitters[0].points[1].z, 0.3f);  // the tip at the nozzle, pointing down
  EXPECT_GT(emitters[0].points[0].z, emitters[0].points[1].z);
  EXPECT_NEAR(emitters[0].scale.y, 0.04, 1e-6);    // the head as wide as the opening
  ASSERT_EQ(drains.size(), 2u);
  EXPECT_EQ(drains[0].type, visualization_msgs::Marker::CUBE);
  EXPECT_NEAR(drains[0].pose.position.x, 0.1, 1e-6);
  EXPECT_NEAR(drains[0].scale.y, 0.1, 1e-6);
  EXPECT_EQ(drains[1].type, visualization_msgs::Marker::SPHERE);
  EXPECT_NEAR(drains[1].scale.x, 0.06, 1e-6);
  EXPECT_EQ(drains[1].header.frame_id, "fluid_domain");
}
