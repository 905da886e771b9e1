#pragma once
// A floating solid (issue 12, part 3): an obstacle the fluid moves. It is a rigid body
// integrated under gravity, the fluid's wrench on it (SolidWrench.h, measured in the step
// just taken) and inelastic contact with the container walls; its pose is the obstacle's.
// Two-way coupling is explicit (the fluid's push of one step moves the body for the next),
// which is stable for bodies not much lighter than the fluid they displace (the added mass
// of the water around a body is of the order of its displaced mass). Scenes refuse bodies
// lighter than kLightestFloatingDensityRatio of the fluid's rest density; below it a body
// is not stable (session 38, `pbf_run` on the floating_bodies scene at d = 0.02 and
// 0.0125 m, 2 s: at 10 and 20 kg/m^3 the raft and the buoy floated; at 5 kg/m^3 the buoy
// leapt out of the water to the lid, at 1 kg/m^3 it reached 2 000 m/s, and at 1e-6 its pose
// overflowed to infinity).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>

#include "pbf_ros/core/Obstacle.h"
#include "pbf_ros/core/SolidWrench.h"

namespace pbf {

// A floating body's density at least this fraction of the fluid's rest density (Scene).
constexpr double kLightestFloatingDensityRatio = 0.02;

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
  // origin) change the velocities (semi-implicit Euler), then the pose follows them. The
  // speed of every point of the body is capped at `max_speed` [m/s] (0 = no cap), as the
  // fluid's is (SolverParams::max_speed_factor). A step that would leave the state non-finite
  // is not taken: the body stays where it was, at rest, and step() returns false.
  bool step(const Wrench& fluid, const Eigen::Vector3d& gravity, double dt, double max_speed = 0.0);
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
