#pragma once
// Which wrench topics a scene has and what each one reports (issue 12, part 2): one per
// solid the fluid can push, `~wrench/<name>`, in the solid's own frame.
//   container      the container (all six walls), in container_frame or fluid_domain
//   obstacle_<k>   scene obstacle k (scene file order), in its tf frame, or fluid_domain
//                  for a static obstacle
//   <link>         a robot link, all of its collision solids together, in the link frame
// A wrench in frame F is the force in F's axes and the torque about F's origin.
// Plain functions, no ROS master: unit-tested in test_ros_units.

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "pbf_ros/core/Scene.h"
#include "pbf_ros/core/SolidWrench.h"
#include "pbf_ros/ros/RobotSource.h"

namespace pbf_ros {

struct WrenchTarget {
  std::string name;                 // topic name under ~wrench/, a valid ROS name
  std::string frame;                // header frame_id
  bool container = false;
  std::vector<std::size_t> obstacles;  // solver obstacle indices summed
};

// The targets of a scene whose obstacles are the file's followed by the robot's.
std::vector<WrenchTarget> wrenchTargets(const pbf::Scene& scene,
                                        const std::vector<RobotLinkSolids>& robot_links,
                                        const std::string& domain_frame);

// `name` as a ROS graph name: characters outside [A-Za-z0-9_] become '_', and a name that
// does not start with a letter gets an 's_' prefix ("2nd-link" -> "s_2nd_link").
std::string topicSafeName(const std::string& name);

// Pose of the target's frame in fluid_domain now (container pose, an obstacle's frame pose
// = pose * offset^-1, or identity for fluid_domain itself).
Eigen::Isometry3d targetFramePose(const WrenchTarget& target, const pbf::Scene& scene,
                                  const Eigen::Isometry3f& container_pose,
                                  const std::vector<pbf::Obstacle>& obstacles);

// The step's wrench on the target, expressed in its frame (pose `frame` in fluid_domain).
pbf::Wrench targetWrench(const WrenchTarget& target, const pbf::SolidWrenches& wrenches,
                         const Eigen::Isometry3f& container_pose,
                         const std::vector<pbf::Obstacle>& obstacles,
                         const Eigen::Isometry3d& frame);

// Every solid together in fluid_domain, torque about its origin.
pbf::Wrench totalWrench(const pbf::SolidWrenches& wrenches, const Eigen::Isometry3f& container_pose,
                        const std::vector<pbf::Obstacle>& obstacles);

}  // namespace pbf_ros
