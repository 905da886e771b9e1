#pragma once
// Shared scenes and helpers of the renderer tests: lattice balls and slabs of particles,
// analytic ray casts, and PNG dumps into the build tree for people to look at.

#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "pbf_ros/render/FluidRenderer.h"
#include "pbf_ros/render/ImageWriter.h"

namespace pbf_test {

inline std::string shaderDir() { return PBF_SHADER_SOURCE_DIR; }
inline std::string imageDir() { return PBF_TEST_IMAGE_DIR; }

// Simple-cubic lattice of the given spacing, every centre within `centre_radius` of `centre`.
inline std::vector<Eigen::Vector3f> latticeBall(const Eigen::Vector3f& centre,
                                                float centre_radius, float spacing) {
  std::vector<Eigen::Vector3f> points;
  const int n = static_cast<int>(std::ceil(centre_radius / spacing));
  for (int k = -n; k <= n; ++k)
    for (int j = -n; j <= n; ++j)
      for (int i = -n; i <= n; ++i) {
        const Eigen::Vector3f offset(i * spacing, j * spacing, k * spacing);
        if (offset.norm() <= centre_radius) points.push_back(centre + offset);
      }
  return points;
}

// A horizontal slab of nx * ny * nz lattice points, top layer of centres at z = top,
// centred on the origin in x and y.
inline std::vector<Eigen::Vector3f> latticeSlab(int nx, int ny, int nz, float spacing,
                                                float top) {
  std::vector<Eigen::Vector3f> points;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        points.emplace_back((i - 0.5f * (nx - 1)) * spacing, (j - 0.5f * (ny - 1)) * spacing,
                            top - k * spacing);
  return points;
}

// Unit ray of pixel (u, v) in the optical camera frame, from the published intrinsics.
inline Eigen::Vector3f pixelRay(const pbf::RenderCamera& camera, int u, int v) {
  const pbf::PinholeIntrinsics k = pbf::intrinsicsOf(camera);
  return Eigen::Vector3f(static_cast<float>((u - k.cx) / k.fx),
                         static_cast<float>((v - k.cy) / k.fy), 1.0f)
      .normalized();
}

// Ray (optical frame, from the eye) against a sphere given in the world frame. Returns the
// distance along the ray or a negative number on a miss.
inline float raySphere(const pbf::RenderCamera& camera, const Eigen::Vector3f& ray,
                       const Eigen::Vector3f& centre_world, float radius) {
  const Eigen::Vector3f c = camera.camera_to_world.inverse() * centre_world;
  const float along = ray.dot(c);
  const float half_chord_sq = radius * radius - (c - along * ray).squaredNorm();
  if (half_chord_sq < 0 || along <= 0) return -1.0f;
  return along - std::sqrt(half_chord_sq);
}

inline double angleDegrees(const Eigen::Vector3f& a, const Eigen::Vector3f& b) {
  const double c = std::max(-1.0, std::min(1.0, static_cast<double>(a.normalized().dot(b.normalized()))));
  return std::acos(c) * 180.0 / M_PI;
}

inline Eigen::Vector3f normalAt(const pbf::RenderOutput& out, int u, int v) {
  const float* n = &out.normals[3 * (static_cast<std::size_t>(v) * out.width + u)];
  return Eigen::Vector3f(n[0], n[1], n[2]);
}

// Writes <name>_image.png, _depth.png, _normals.png, _thickness.png for what `out` holds.
inline void saveImages(const std::string& name, const pbf::RenderOutput& out) {
  const std::string stem = imageDir() + "/" + name;
  if (!out.rgba.empty()) pbf::writePng(stem + "_image.png", out.width, out.height, 4, out.rgba);
  if (!out.depth.empty())
    pbf::writePng(stem + "_depth.png", out.width, out.height, 4, pbf::depthToRgba(out.depth));
  if (!out.normals.empty())
    pbf::writePng(stem + "_normals.png", out.width, out.height, 4,
                  pbf::normalsToRgba(out.normals));
  if (!out.thickness.empty())
    pbf::writePng(stem + "_thickness.png", out.width, out.height, 4,
                  pbf::scalarToRgba(out.thickness));
}

inline pbf::RenderRequest everything() {
  pbf::RenderRequest request;
  request.image = request.depth = request.thickness = request.normals = true;
  return request;
}

}  // namespace pbf_test
