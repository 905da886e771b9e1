#pragma once
// Reading a robot's mesh file (package://, file://, or a path; STL, DAE, OBJ, ... through
// geometric_shapes and assimp, as MoveIt and rviz do) into the core's TriangleMesh.

#include <Eigen/Core>
#include <string>

#include "pbf_ros/core/TriangleMesh.h"

namespace pbf_ros {

// The mesh at `uri`, its vertices multiplied by `scale` (URDF <mesh scale>). False, with
// `error` saying why (unresolvable package, missing file, unreadable format, no triangles),
// when there is no mesh to read. Whether the mesh can bound a solid is TriangleMesh::validate.
bool loadMeshResource(const std::string& uri, const Eigen::Vector3d& scale, pbf::TriangleMesh& mesh,
                      std::string& error);

}  // namespace pbf_ros
