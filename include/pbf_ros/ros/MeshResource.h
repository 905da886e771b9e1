#pragma once
// Reading a robot's mesh file (package://, file://, or a path; nothing is downloaded; STL,
// DAE, OBJ, ... through geometric_shapes and assimp, as MoveIt and rviz do) into the core's
// TriangleMesh.

#include <Eigen/Core>
#include <cstdint>
#include <string>

#include "pbf_ros/core/TriangleMesh.h"

namespace pbf_ros {

// A collision mesh file is read only up to this size: a 50 000-triangle mesh (the most a
// solid may have) is 2.5 MB as binary STL, about 13 MB as ASCII STL.
constexpr std::uint64_t kMaxMeshFileBytes = std::uint64_t{32} << 20;

// The mesh at `uri`, its vertices multiplied by `scale` (URDF <mesh scale>). False, with
// `error` saying why (unresolvable package, missing file, not a regular file, a file over
// kMaxMeshFileBytes, a download (other schemes than package:// and file://), unreadable
// format, no triangles), when there is no mesh to read. Whether the mesh can bound a solid
// is TriangleMesh::validate.
bool loadMeshResource(const std::string& uri, const Eigen::Vector3d& scale, pbf::TriangleMesh& mesh,
                      std::string& error);

}  // namespace pbf_ros
