#pragma once
// Moves what a scene attaches to tf frames (its container, its obstacles, the fluid it is
// seeded with) to where tf says those frames are. A frame moved by any node (a demo driver,
// a robot) then carries the solid, and the solid pushes the fluid.

#include <memory>
#include <string>
#include <vector>

#include <ros/time.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "pbf_ros/core/PbfSolver.h"
#include "pbf_ros/core/Scene.h"

namespace pbf_ros {

class TfAttachments {
 public:
  explicit TfAttachments(std::string domain_frame);
  // Reads `buffer`, filled by the caller, instead of subscribing to /tf (unit tests: no
  // master needed).
  TfAttachments(std::string domain_frame, std::shared_ptr<tf2_ros::Buffer> buffer);

  // True when the scene attaches anything to a tf frame (no tf work otherwise).
  static bool needed(const pbf::Scene& scene);

  // Sets the solver's container pose and obstacle poses from tf (domain_frame <- frame) at
  // `time`, interpolated between the transforms received. When the frame's publisher has
  // not sent `time` yet, waits for it at most `max_wait` wall seconds (a wall clock: ros::Time
  // may be the node's own /clock, which does not move while it waits), then takes the latest
  // pose. ros::Time(0) = the latest pose. A frame tf does not know keeps its previous pose;
  // the names of frames unknown for longer than a grace period after the last restart() are
  // returned so the caller can warn (a demo's frame publisher starts after the node).
  std::vector<std::string> update(const pbf::Scene& scene, pbf::PbfSolver& solver,
                                  const ros::Time& time, double max_wait);

  // The pose of `frame` now (latest transform); false when tf does not know it.
  bool currentPose(const std::string& frame, Eigen::Isometry3f& pose);

  // A new scene (or reset): the grace period for missing frames starts again.
  void restart();

 private:
  void listen();  // subscribes to /tf once a scene needs it (unless given a buffer)
  bool lookup(const std::string& frame, const ros::Time& time, double max_wait,
              Eigen::Isometry3f& pose) const;

  std::string domain_frame_;
  ros::WallTime started_;
  std::shared_ptr<tf2_ros::Buffer> buffer_;
  std::unique_ptr<tf2_ros::TransformListener> listener_;  // created on first use
};

}  // namespace pbf_ros
