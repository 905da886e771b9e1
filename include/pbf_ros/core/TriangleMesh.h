#pragma once
// A triangle mesh as loaded from a robot's mesh file (STL, DAE, ...): the input from which a
// mesh obstacle's signed distance grid is built. Plain data plus the checks that decide
// whether it can bound a solid at all.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace pbf {

struct TriangleMesh {
  std::vector<Eigen::Vector3f> vertices;  // [m], in the solid's local frame
  std::vector<Eigen::Vector3i> triangles;  // indices into vertices

  // Empty when the mesh can bound a solid; otherwise what is wrong with it: no triangles,
  // non-finite vertices, indices out of range, or no enclosed volume (flat, or every
  // triangle degenerate).
  std::string validate() const;

  // Volume enclosed (divergence theorem), positive for outward-facing triangles, negative
  // for an inside-out mesh. Meaningful for closed meshes only.
  double signedVolume() const;
  // Edges used by an odd number of triangles: 0 for a closed (watertight) mesh.
  std::size_t openEdges() const;
  // Largest |vertex|: a sphere about the local origin containing the whole mesh.
  float boundingRadius() const;
  // The box around the vertices the triangles use (empty without triangles).
  Eigen::AlignedBox3f bounds() const;
};

}  // namespace pbf
