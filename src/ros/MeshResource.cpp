#include "pbf_ros/ros/MeshResource.h"

#include <geometric_shapes/mesh_operations.h>
#include <ros/package.h>
#include <sys/stat.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>

#include "ConsoleBridgeCapture.h"

namespace pbf_ros {

namespace {

// The file behind a package://, file:// or plain-path URI; empty, with `error`, when there
// is none to read.
std::string localPath(const std::string& uri, std::string& error) {
  const std::string package = "package://", file = "file://";
  if (uri.compare(0, package.size(), package) == 0) {
    const std::string rest = uri.substr(package.size());
    const std::size_t slash = rest.find('/');
    const std::string name = rest.substr(0, slash);
    const std::string root = name.empty() ? std::string() : ros::package::getPath(name);
    if (root.empty()) {
      error = "package '" + name + "' is not found (is its workspace sourced?)";
      return {};
    }
    return slash == std::string::npos ? root : root + rest.substr(slash);
  }
  if (uri.compare(0, file.size(), file) == 0) return uri.substr(file.size());
  if (uri.find("://") != std::string::npos) {
    error = "only local meshes are read (package://, file:// or a path): a download could be "
            "of any size";
    return {};
  }
  return uri;
}

// Whether `path` is a regular file small enough to hold a collision mesh; resource_retriever
// and assimp read a whole file into memory before anything counts its triangles, and a mesh
// at /dev/zero grew the node by 0.35 GB a second (a 50 MB visual mesh: 0.4 GB before it was
// refused for its triangles).
bool readableMeshFile(const std::string& path, std::string& error) {
  struct stat st {};
  if (stat(path.c_str(), &st) != 0) {
    error = std::string("no such file (") + std::strerror(errno) + ")";
    return false;
  }
  if (!S_ISREG(st.st_mode)) {
    error = "not a regular file";
    return false;
  }
  if (static_cast<std::uint64_t>(st.st_size) > kMaxMeshFileBytes) {
    char size[32];
    std::snprintf(size, sizeof size, "%.1f MiB", static_cast<double>(st.st_size) / (1 << 20));
    error = std::string(size) + ", more than the " + std::to_string(kMaxMeshFileBytes >> 20) +
            " MiB a collision mesh file may have (a visual mesh? give a simplified one as collision geometry)";
    return false;
  }
  return true;
}

}  // namespace

bool loadMeshResource(const std::string& uri, const Eigen::Vector3d& scale, pbf::TriangleMesh& mesh,
                      std::string& error) {
  std::string why;
  const std::string path = localPath(uri, why);
  if (path.empty() || !readableMeshFile(path, why)) {
    error = "cannot read mesh '" + uri + "': " + why;
    return false;
  }
  std::unique_ptr<shapes::Mesh> loaded;
  ConsoleBridgeCapture log;
  try {
    loaded.reset(shapes::createMeshFromResource(uri, scale));
  } catch (const std::exception& e) {  // resource_retriever throws for unknown packages
    error = "cannot read mesh '" + uri + "': " + e.what();
    return false;
  }
  if (!loaded) {
    error = "cannot read mesh '" + uri + "'" + (log.text().empty() ? "" : ": " + log.text());
    return false;
  }
  mesh.vertices.resize(loaded->vertex_count);
  for (unsigned int i = 0; i < loaded->vertex_count; ++i)
    mesh.vertices[i] = Eigen::Vector3d(loaded->vertices[3 * i], loaded->vertices[3 * i + 1],
                                       loaded->vertices[3 * i + 2]).cast<float>();
  mesh.triangles.resize(loaded->triangle_count);
  for (unsigned int t = 0; t < loaded->triangle_count; ++t)
    mesh.triangles[t] = Eigen::Vector3i(int(loaded->triangles[3 * t]), int(loaded->triangles[3 * t + 1]),
                                        int(loaded->triangles[3 * t + 2]));
  return true;
}

}  // namespace pbf_ros
