#pragma once
// Solid obstacles in the flow: boxes, spheres, capsules, cylinders and triangle meshes
// (through a signed distance grid built once at load), static or moved each step (the ROS
// layer attaches them to tf frames: scene obstacles, or a robot's links). Particles are
// kept out of them and, like the container walls, get density from them (Boundaries.h), so
// they do not stick.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <string>

#include "pbf_ros/core/SignedDistanceGrid.h"

namespace pbf {

struct Obstacle {
  enum class Shape { Box, Sphere, Capsule, Cylinder, Mesh };
  Shape shape = Shape::Sphere;
  Eigen::Vector3f half_extents = Eigen::Vector3f::Constant(0.05f);  // Box [m]
  float radius = 0.05f;       // Sphere, Capsule, Cylinder [m]
  // Capsule: half the segment length; Cylinder: half the length between its flat caps;
  // both along the local z axis [m].
  float half_length = 0.05f;
  // Mesh: the solid's signed distance in its local frame, shared by copies (immutable).
  std::shared_ptr<const SignedDistanceGrid> sdf;
  // tf frame the obstacle is attached to ("" = static in fluid_domain). With a frame,
  // `offset` is its pose in that frame; the node updates `pose` from tf every step.
  std::string frame;
  Eigen::Isometry3f offset = Eigen::Isometry3f::Identity();
  Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();  // in fluid_domain

  // Signed distance from p (fluid_domain) to the surface, negative inside, and the
  // outward unit normal at the closest surface point.
  float signedDistance(const Eigen::Vector3f& p, Eigen::Vector3f& normal) const;
  // Radius of a sphere around pose.translation() containing the whole obstacle.
  float boundingRadius() const;
  // Half the sides of the box containing the obstacle in its own axes (a mesh: the sphere's
  // box, boundingRadius()).
  Eigen::Vector3f localHalfExtents() const;
  // Empty when usable; otherwise what is wrong.
  std::string validate() const;
};

}  // namespace pbf
