#pragma once
// The render camera and the pinhole model that agrees with it pixel for pixel.
//
// The pose uses the OPTICAL convention of ROS cameras (REP 103/118): z forward, x right,
// y down, so the node can publish it as the `fluid_camera_optical` frame unchanged.
// Pixel (u, v) has its centre at integer coordinates, rows counted from the top, exactly as
// sensor_msgs/CameraInfo expects; intrinsicsOf() gives the K the GL projection realises.

#include <Eigen/Geometry>

namespace pbf {

struct RenderCamera {
  Eigen::Isometry3f camera_to_world = Eigen::Isometry3f::Identity();
  float vertical_fov = 1.0471976f;  // radians (60 degrees)
  int width = 640;
  int height = 480;
  float near_clip = 0.02f;  // metres along the optical axis
  float far_clip = 100.0f;
};

struct PinholeIntrinsics {
  double fx = 0, fy = 0, cx = 0, cy = 0;
};

// Square pixels: fx = fy = (height / 2) / tan(vertical_fov / 2); the principal point is
// the image centre, (width - 1) / 2 and (height - 1) / 2 in pixel-centre coordinates.
PinholeIntrinsics intrinsicsOf(const RenderCamera& camera);

// Projects a world point with those intrinsics; returns false behind the camera.
bool projectToPixel(const RenderCamera& camera, const Eigen::Vector3f& world_point,
                    Eigen::Vector2f& pixel, float& depth);

// OpenGL matrices for the same camera (GL view space: x right, y up, z backwards).
Eigen::Matrix4f glViewFromWorld(const RenderCamera& camera);
Eigen::Matrix4f glProjection(const RenderCamera& camera);

// An optical-frame pose at `eye` looking at `target`, with image "up" as close to world
// `up` as possible. Convenient for tests, tools and default camera placement.
Eigen::Isometry3f lookAt(const Eigen::Vector3f& eye, const Eigen::Vector3f& target,
                         const Eigen::Vector3f& up = Eigen::Vector3f::UnitZ());

}  // namespace pbf
