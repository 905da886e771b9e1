#pragma once
// Lets a user move the scene's free obstacles while the fluid runs (those with no tf frame,
// not floating, not a robot link: nothing else decides their pose): by dragging an
// interactive marker in rviz (server ~obstacle_markers, one 6-DOF marker per free obstacle)
// or from code with a geometry_msgs/PoseStamped on ~obstacle_pose/obstacle_<k> (k as in
// ~wrench/obstacle_<k>; the pose in header.frame_id, "" = the fluid frame).
//
// A request only sets a target. Between steps (simulation thread) each obstacle moves
// toward its target by at most half a particle spacing at any of its surface points, so a
// far jump sweeps the fluid aside over a few steps instead of landing inside it. A
// non-finite pose or an unknown frame is refused with a warning naming it; the running
// simulation never sees it.

#include <Eigen/Geometry>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <geometry_msgs/Pose.h>
#include <geometry_msgs/PoseStamped.h>
#include <interactive_markers/interactive_marker_server.h>
#include <ros/ros.h>

#include "pbf_ros/core/PbfSolver.h"
#include "pbf_ros/core/Scene.h"

namespace pbf_ros {

// One step from `current` toward `target`: the whole way if no point within `radius` of the
// origin moves farther than `max_move`, else that fraction of it (translation linear,
// rotation by slerp).
Eigen::Isometry3f stepToward(const Eigen::Isometry3f& current, const Eigen::Isometry3f& target,
                             float max_move, float radius);

// A message pose as an isometry; false (and why) when a number is not finite or the
// quaternion has (nearly) zero length. The quaternion is normalised.
bool poseFromMsg(const geometry_msgs::Pose& msg, Eigen::Isometry3f& pose, std::string& why);

class ObstacleMover {
 public:
  // `frame_pose(frame, pose)` gives the pose of a tf frame in the fluid frame (called on the
  // simulation thread, in apply()).
  using FramePose = std::function<bool(const std::string&, Eigen::Isometry3f&)>;
  ObstacleMover(ros::NodeHandle private_nh, std::string domain_frame, FramePose frame_pose);

  // A new scene (simulation thread, after every rebuild): markers and topics for its free
  // obstacles (`robot_obstacles` lists the robot links' indices); pending targets are dropped.
  void setScene(const pbf::Scene& scene, const std::vector<std::size_t>& robot_obstacles);

  // Simulation thread, between steps: moves obstacles toward their targets (solver and
  // scene poses). True when any moved.
  bool apply(pbf::PbfSolver& solver, pbf::Scene& scene);

  // Indices of the obstacles that can be moved.
  std::vector<std::size_t> freeObstacles() const;

 private:
  struct Target {
    Eigen::Isometry3f pose;
    std::string frame;  // "" = the fluid frame
  };
  void request(std::size_t index, std::uint64_t generation, const std::string& frame,
               const geometry_msgs::Pose& pose, const std::string& source);
  void onFeedback(const visualization_msgs::InteractiveMarkerFeedbackConstPtr& feedback);

  ros::NodeHandle pnh_;
  std::string domain_frame_;
  FramePose frame_pose_;
  interactive_markers::InteractiveMarkerServer server_;
  mutable std::mutex mutex_;               // guards what callbacks and the simulation share
  std::uint64_t generation_ = 0;           // per scene: stale callbacks are ignored
  std::vector<std::size_t> free_;          // movable obstacle indices
  std::map<std::size_t, Target> targets_;  // pending moves
  std::vector<ros::Subscriber> subscribers_;
  ros::WallTime last_marker_update_;       // simulation thread
};

}  // namespace pbf_ros
