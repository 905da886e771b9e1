#pragma once
// Everything solid the fluid meets in one step: the container (a box with a pose in the
// fluid frame, moved by the node when it is attached to a tf frame) and the obstacles.
//
// Solids lend density to the particles near them, as ghost fluid at rest beyond their
// surface (LatticeBoundary.h): exactly the missing density for a resting lattice at a flat
// wall, an edge or a corner of the container and of box obstacles; curved obstacles scale
// the flat-wall value by how much of the kernel the curved solid really covers. They also
// keep particles out (project), and carry them along by friction (contact).
// Built once per pass from the solver's state; cheap to copy.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "pbf_ros/core/LatticeBoundary.h"
#include "pbf_ros/core/Obstacle.h"

namespace pbf {

class SolidBoundaries {
 public:
  // `lattice` (for the spacing and support radius of the step) must outlive this object.
  SolidBoundaries(const Eigen::AlignedBox3f& container, const Eigen::Isometry3f& container_pose,
                  const std::vector<Obstacle>& obstacles, const LatticeBoundary& lattice,
                  float particle_radius);

  // Density fraction (multiply by rho0) lent by walls and obstacles near p, and its
  // gradient with respect to p. False (nothing added) when no solid is near: the common case.
  bool density(const Eigen::Vector3f& p, float& fraction, Eigen::Vector3f& gradient) const;

  // p moved out of every obstacle and into the container, keeping particle_radius from
  // each surface. The container is applied last: no particle ever leaves it.
  Eigen::Vector3f project(const Eigen::Vector3f& p) const;

  // For a particle at p (after project): whether a surface lies within `reach` of it, its
  // unit normal, and how far that surface point moved during the step (from the previous
  // poses). Used for wall friction.
  bool contact(const Eigen::Vector3f& p, float reach, Eigen::Vector3f& normal,
               Eigen::Vector3f& surface_motion) const;

  // Poses at the start of the step, for surface_motion (default: not moving).
  void setPreviousPoses(const Eigen::Isometry3f& container,
                        const std::vector<Eigen::Isometry3f>* obstacles) {
    prev_container_ = container;
    prev_obstacles_ = obstacles;
  }

  bool hasContainer() const { return has_container_; }

 private:
  bool containerDensity(const Eigen::Vector3f& q, float& fraction, Eigen::Vector3f& gradient) const;
  bool boxDensity(const Obstacle& o, const Eigen::Vector3f& p, float& fraction,
                  Eigen::Vector3f& gradient) const;
  bool curvedDensity(const Obstacle& o, const Eigen::Vector3f& p, float& fraction,
                     Eigen::Vector3f& gradient) const;

  bool has_container_;
  bool posed_;  // container pose is not the identity
  Eigen::AlignedBox3f box_;
  Eigen::Isometry3f pose_, inverse_;
  const std::vector<Obstacle>* obstacles_;
  Eigen::Isometry3f prev_container_ = Eigen::Isometry3f::Identity();
  const std::vector<Eigen::Isometry3f>* prev_obstacles_ = nullptr;
  const LatticeBoundary* lattice_;
  float reach_, radius_;
};

}  // namespace pbf
