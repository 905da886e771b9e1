#pragma once
// A robot's collision geometry as fluid solids: each <collision> of each selected URDF link
// becomes an Obstacle attached to the link's tf frame at the collision origin (box, sphere,
// cylinder; a mesh through a signed distance grid built here, once). Whatever cannot be
// used is reported, naming the link and what was wrong, and the rest of the robot still
// takes part. No ROS master is needed: the node passes the robot_description string.

#include <string>
#include <vector>

#include "pbf_ros/core/Obstacle.h"
#include "pbf_ros/core/Scene.h"
#include "pbf_ros/core/SignedDistanceGrid.h"

namespace pbf_ros {

// All of a robot's mesh grids together keep at most this much memory: each grid is bounded
// (SignedDistanceGridOptions::max_bytes while it is built, 4 of those 9 bytes per node kept),
// but a robot of 256 solids could have asked for 28 GiB. A mesh whose grid would not fit in
// what is left is refused by name. The shipped arm's grids take 0.37 MiB at d = 0.01 m.
constexpr std::size_t kMaxMeshGridBytesInAll = std::size_t(512) << 20;

struct UrdfSolidsOptions {
  // Which links take part. Both empty: every link with collision geometry. `links` names
  // them (each must exist and have collision geometry); `link_regex` (ECMAScript, matched
  // against the whole name) keeps only the links it matches.
  std::vector<std::string> links;
  std::string link_regex;
  // Resolution and margin of mesh grids; the node uses cell = particle spacing / 2 and
  // band = support radius + particle spacing.
  pbf::SignedDistanceGridOptions sdf;
  // What the robot's mesh grids may keep in all (bytes).
  std::size_t max_mesh_grid_bytes = kMaxMeshGridBytesInAll;
  // At most this many solids take part (a scene may hold as many obstacles); the rest are
  // left out with one problem that says how many.
  std::size_t max_solids = pbf::kMaxObstacles;
};

// A mesh with more triangles is refused: gridding costs ~20 us per triangle (2 s for
// 100 000 at a 1 cm spacing), on every ~reset and scene switch, while the fluid waits. A
// collision mesh needs far fewer; a visual mesh given as collision geometry has this many.
constexpr std::size_t kMaxMeshTriangles = 50000;

struct UrdfSolid {
  std::string link;       // = obstacle.frame
  std::string name;       // "<link>/<collision name>" or "<link>/collision_<i>"
  std::string geometry;   // "box", "sphere", "cylinder" or "mesh '<uri>'"
  pbf::Obstacle obstacle;  // frame = link, offset = collision origin, pose = offset
};

struct UrdfSolids {
  std::string robot_name;
  std::vector<UrdfSolid> solids;
  // One line per problem, each naming the link (or the URDF) and what was wrong; a solid
  // that takes part with a flaw (a mesh that is not closed) is named here too.
  std::vector<std::string> problems;

  std::vector<pbf::Obstacle> obstacles() const;
  // Memory held by the mesh grids, a grid shared by several solids counted once [bytes].
  std::size_t sdfBytes() const;
};

UrdfSolids urdfSolids(const std::string& urdf_xml, const UrdfSolidsOptions& options);

}  // namespace pbf_ros
