#pragma once
// A floating solid (issue 12, part 3): an obstacle the fluid moves. It is a rigid body
// integrated under gravity, the fluid's wrench on it (SolidWrench.h, measured in the step
// just taken) and inelastic contact with the container walls; its pose is the obstacle's.
// Two-way coupling is explicit (the fluid's push of one step moves the body for the next),
// which is stable for bodies not much lighter than the fluid they displace (the added mass
// of the water around a body is of the order of its displaced mass).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>

#include "pbf_ros/core/Obstacle.h"
#include "pbf_ros/core/SolidWrench.h"

namespace pbf {

// Volume of an obstacle's solid [m^3] (a mesh: the volume its triangles enclose).
double solidVolume(const Obstacle& o);
// Inertia tensor about the obstacle's origin, in its local axes, for a uniform solid of
// `mass` (boxes, spheres, cylinders exactly; a capsule as its cylinder plus two half balls; a
// mesh as the box bounding its vertices).
Eigen::Matrix3d solidInertia(const Obstacle& o, double mass);

class RigidBody {
 public:
  // Mass [kg] and inertia about the origin in body axes; throws std::invalid_argument for a
  // mass or inertia that is not positive and finite.
  RigidBody(const Obstacle& shape, double mass, const Eigen::Matrix3d& inertia);

  // One step of dt: gravity and `fluid` (force in fluid_domain, torque about the body's
  // origin) change the velocities (semi-implicit Euler), then the pose follows them.
  void step(const Wrench& fluid, const Eigen::Vector3d& gravity, double dt);
  // Keeps the body inside the container (`box` in its frame at `container_pose`): points of
  // the body beyond a wall are moved back and their velocity into the wall is removed
  // (an inelastic impulse at the point, so a resting body stays and a sliding one turns).
  void collide(const Eigen::AlignedBox3f& box, const Eigen::Isometry3f& container_pose);

  const Obstacle& shape() const { return shape_; }  // with the current pose
  const Eigen::Vector3d& linearVelocity() const { return v_; }
  const Eigen::Vector3d& angularVelocity() const { return w_; }
  double mass() const { return mass_; }
  double kineticEnergy() const;

 private:
  Obstacle shape_;
  double mass_;
  Eigen::Matrix3d inertia_body_, inverse_inertia_body_;
  Eigen::Vector3d x_;         // position of the origin
  Eigen::Quaterniond q_;      // orientation
  Eigen::Vector3d v_ = Eigen::Vector3d::Zero(), w_ = Eigen::Vector3d::Zero();
};

}  // namespace pbf
