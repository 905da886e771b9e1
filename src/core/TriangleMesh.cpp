#include "pbf_ros/core/TriangleMesh.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

namespace pbf {

std::string TriangleMesh::validate() const {
  std::ostringstream err;
  if (triangles.empty()) return "mesh has no triangles";
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    if (!vertices[i].allFinite()) {
      err << "mesh vertex " << i << " is not finite (" << vertices[i].transpose() << ")";
      return err.str();
    }
  }
  const int n = static_cast<int>(vertices.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const Eigen::Vector3i& tri = triangles[t];
    if ((tri.array() < 0).any() || (tri.array() >= n).any()) {
      err << "mesh triangle " << t << " uses vertex indices (" << tri.transpose()
          << ") outside the " << n << " vertices";
      return err.str();
    }
  }
  // Compare against the bounding box so that the test does not depend on the mesh's units.
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(INFINITY), hi = -lo;
  for (const auto& tri : triangles)
    for (int k = 0; k < 3; ++k) {
      lo = lo.cwiseMin(vertices[tri[k]]);
      hi = hi.cwiseMax(vertices[tri[k]]);
    }
  const double box_volume = double(hi.x() - lo.x()) * (hi.y() - lo.y()) * (hi.z() - lo.z());
  const double volume = std::abs(signedVolume());
  if (!(box_volume > 0.0) || volume < 1e-6 * box_volume) {
    err << "mesh encloses no volume (" << volume << " m^3 inside a bounding box of "
        << (hi - lo).transpose() << " m): flat, or every triangle degenerate";
    return err.str();
  }
  return "";
}

double TriangleMesh::signedVolume() const {
  double six_v = 0.0;
  for (const auto& tri : triangles) {
    const Eigen::Vector3d a = vertices[tri[0]].cast<double>(), b = vertices[tri[1]].cast<double>(),
                          c = vertices[tri[2]].cast<double>();
    six_v += a.dot(b.cross(c));
  }
  return six_v / 6.0;
}

std::size_t TriangleMesh::openEdges() const {
  std::vector<std::pair<int, int>> edges;
  edges.reserve(3 * triangles.size());
  for (const auto& tri : triangles)
    for (int k = 0; k < 3; ++k) {
      const int a = tri[k], b = tri[(k + 1) % 3];
      edges.emplace_back(std::min(a, b), std::max(a, b));
    }
  std::sort(edges.begin(), edges.end());
  std::size_t open = 0;
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    open += (j - i) % 2;
    i = j;
  }
  return open;
}

Eigen::AlignedBox3f TriangleMesh::bounds() const {
  Eigen::AlignedBox3f box;  // empty
  for (const auto& tri : triangles)
    for (int k = 0; k < 3; ++k) box.extend(vertices[tri[k]]);
  return box;
}

float TriangleMesh::boundingRadius() const {
  float r2 = 0.0f;
  for (const auto& v : vertices) r2 = std::max(r2, v.squaredNorm());
  return std::sqrt(r2);
}

}  // namespace pbf
