#include "pbf_ros/render/RenderCamera.h"

#include <cmath>

namespace pbf {

PinholeIntrinsics intrinsicsOf(const RenderCamera& camera) {
  PinholeIntrinsics k;
  k.fy = 0.5 * camera.height / std::tan(0.5 * static_cast<double>(camera.vertical_fov));
  k.fx = k.fy;
  // GL puts pixel i's centre at window coordinate i + 0.5 and the optical axis at width/2;
  // in pixel-centre coordinates that is (width - 1) / 2.
  k.cx = 0.5 * camera.width - 0.5;
  k.cy = 0.5 * camera.height - 0.5;
  return k;
}

bool projectToPixel(const RenderCamera& camera, const Eigen::Vector3f& world_point,
                    Eigen::Vector2f& pixel, float& depth) {
  const Eigen::Vector3f p = camera.camera_to_world.inverse() * world_point;
  depth = p.z();
  if (depth <= 0) return false;
  const PinholeIntrinsics k = intrinsicsOf(camera);
  pixel = Eigen::Vector2f(static_cast<float>(k.fx * p.x() / p.z() + k.cx),
                          static_cast<float>(k.fy * p.y() / p.z() + k.cy));
  return true;
}

Eigen::Matrix4f glViewFromWorld(const RenderCamera& camera) {
  // Optical (x right, y down, z forward) to GL view (x right, y up, z backwards).
  Eigen::Matrix4f gl_from_optical = Eigen::Matrix4f::Identity();
  gl_from_optical(1, 1) = -1;
  gl_from_optical(2, 2) = -1;
  return gl_from_optical * camera.camera_to_world.inverse().matrix();
}

Eigen::Matrix4f glProjection(const RenderCamera& camera) {
  const float f = 1.0f / std::tan(0.5f * camera.vertical_fov);
  const float aspect = static_cast<float>(camera.width) / static_cast<float>(camera.height);
  const float n = camera.near_clip, fa = camera.far_clip;
  Eigen::Matrix4f p = Eigen::Matrix4f::Zero();
  p(0, 0) = f / aspect;
  p(1, 1) = f;
  p(2, 2) = -(fa + n) / (fa - n);
  p(2, 3) = -2.0f * fa * n / (fa - n);
  p(3, 2) = -1.0f;
  return p;
}

Eigen::Isometry3f lookAt(const Eigen::Vector3f& eye, const Eigen::Vector3f& target,
                         const Eigen::Vector3f& up) {
  const Eigen::Vector3f z = (target - eye).normalized();
  Eigen::Vector3f x = z.cross(up);
  if (x.squaredNorm() < 1e-12f) x = z.unitOrthogonal();  // looking straight along `up`
  x.normalize();
  const Eigen::Vector3f y = z.cross(x);  // image down
  Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();
  pose.linear().col(0) = x;
  pose.linear().col(1) = y;
  pose.linear().col(2) = z;
  pose.translation() = eye;
  return pose;
}

}  // namespace pbf
