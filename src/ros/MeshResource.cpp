#include "pbf_ros/ros/MeshResource.h"

#include <geometric_shapes/mesh_operations.h>

#include <memory>

#include "ConsoleBridgeCapture.h"

namespace pbf_ros {

bool loadMeshResource(const std::string& uri, const Eigen::Vector3d& scale, pbf::TriangleMesh& mesh,
                      std::string& error) {
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
