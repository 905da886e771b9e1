#pragma once
// Small closed triangle meshes for the signed distance tests: a box, and solids of
// revolution (a UV sphere, a thick-walled open cup) from a profile turned about z.

#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "pbf_ros/core/TriangleMesh.h"

namespace pbf_test {

// Box [-half, half], outward triangles, moved by `pose`.
inline pbf::TriangleMesh boxMesh(const Eigen::Vector3f& half,
                                 const Eigen::Isometry3f& pose = Eigen::Isometry3f::Identity()) {
  pbf::TriangleMesh m;
  for (int c = 0; c < 8; ++c)
    m.vertices.push_back(pose * Eigen::Vector3f((c & 1 ? 1 : -1) * half.x(), (c & 2 ? 1 : -1) * half.y(),
                                                (c & 4 ? 1 : -1) * half.z()));
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.triangles.emplace_back(q[0], q[1], q[2]);
    m.triangles.emplace_back(q[0], q[2], q[3]);
  }
  return m;
}

// The closed polygon `profile` (r >= 0, z) turned about the z axis in `segments` steps.
// Points on the axis (r = 0) become one vertex; triangles that would collapse are left out.
inline pbf::TriangleMesh latheMesh(const std::vector<Eigen::Vector2f>& profile, int segments) {
  pbf::TriangleMesh m;
  std::vector<int> first(profile.size());
  for (std::size_t i = 0; i < profile.size(); ++i) {
    first[i] = static_cast<int>(m.vertices.size());
    const float r = profile[i].x(), z = profile[i].y();
    if (r == 0.0f) {
      m.vertices.emplace_back(0.0f, 0.0f, z);
      continue;
    }
    for (int k = 0; k < segments; ++k) {
      const float a = 2.0f * float(M_PI) * k / segments;
      m.vertices.emplace_back(r * std::cos(a), r * std::sin(a), z);
    }
  }
  auto vertex = [&](std::size_t i, int k) {
    return profile[i].x() == 0.0f ? first[i] : first[i] + k % segments;
  };
  for (std::size_t i = 0; i < profile.size(); ++i) {
    const std::size_t j = (i + 1) % profile.size();
    for (int k = 0; k < segments; ++k) {
      const int a = vertex(i, k), b = vertex(i, k + 1), c = vertex(j, k + 1), d = vertex(j, k);
      if (a != b && b != c && a != c) m.triangles.emplace_back(a, c, b);
      if (a != c && c != d && a != d) m.triangles.emplace_back(a, d, c);
    }
  }
  return m;
}

inline pbf::TriangleMesh sphereMesh(float radius, int segments) {
  std::vector<Eigen::Vector2f> profile;
  const int rings = segments / 2;
  for (int i = 0; i <= rings; ++i) {  // south pole to north pole; the axis closes it
    const float t = -0.5f * float(M_PI) + float(M_PI) * i / rings;
    profile.emplace_back(i == 0 || i == rings ? 0.0f : radius * std::cos(t), radius * std::sin(t));
  }
  return latheMesh(profile, segments);
}

// Open-top cup standing on z = 0: outer radius, height, wall and bottom thickness.
inline pbf::TriangleMesh cupMesh(float radius, float height, float wall, int segments) {
  return latheMesh({{0.0f, 0.0f}, {radius, 0.0f}, {radius, height}, {radius - wall, height},
                    {radius - wall, wall}, {0.0f, wall}},
                   segments);
}

}  // namespace pbf_test
