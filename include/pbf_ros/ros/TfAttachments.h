#pragma once
// Moves what a scene attaches to tf frames (its container, its obstacles, the fluid it is
// seeded with) to where tf says those frames are. A frame moved by any node (a demo driver,
// a robot) then carries the solid, and the solid pushes the fluid.

#include <map>
#include <memory>
#include <string>
#include <utility>
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

  // What one update could not do, by frame (each frame named once).
  struct Report {
    std::vector<std::string> missing;     // tf does not know them (named after a grace period)
    std::vector<std::string> non_finite;  // tf has them, with a pose that is not finite
    // Behind: the publisher's next pose (its latest stamp plus its interval) is more than
    // 0.25 simulated s overdue at the step's time; the solid holds the latest pose, this
    // many simulated s old.
    std::vector<std::pair<std::string, double>> behind;
  };

  // Sets the solver's container pose and obstacle poses from tf (domain_frame <- frame) at
  // `time`, interpolated between the transforms received; each frame is looked up once,
  // however many solids it carries. When the frame's publisher has not sent `time` yet and
  // its next pose is due (its latest stamp plus the interval between its last two), waits
  // at most `max_wait` wall seconds (a wall clock: ros::Time may be the node's own /clock,
  // which does not move while it waits), then takes the latest pose. A publisher between two
  // of its poses is not waited for (on the node's /clock it cannot send the next one before
  // the step), nor one already waited for in vain since its latest pose (a dead publisher
  // costs one wait, not one per step). ros::Time(0) = the latest pose. A frame tf does not
  // know keeps its previous pose; frames unknown for longer than a grace period after the
  // last restart() are reported so the caller can warn (a demo's frame publisher starts
  // after the node).
  Report update(const pbf::Scene& scene, pbf::PbfSolver& solver, const ros::Time& time,
                double max_wait);

  // The pose of `frame` now (latest transform); false when tf does not know it.
  bool currentPose(const std::string& frame, Eigen::Isometry3f& pose);

  // A new scene (or reset): the grace period for missing frames starts again.
  void restart();

 private:
  enum class Lookup { kFound, kUnknown, kNonFinite };
  // The stamps of a frame's latest poses as the lookups saw them (the publisher's interval).
  struct PublisherClock {
    ros::Time latest, previous;
    ros::Time waited_in_vain;  // the latest stamp when a wait for the next one timed out
  };

  void listen();  // subscribes to /tf once a scene needs it (unless given a buffer)
  Lookup lookup(const std::string& frame, const ros::Time& time, double max_wait,
                Eigen::Isometry3f& pose, double* behind = nullptr);

  std::string domain_frame_;
  ros::WallTime started_;
  std::shared_ptr<tf2_ros::Buffer> buffer_;
  std::unique_ptr<tf2_ros::TransformListener> listener_;  // created on first use
  std::map<std::string, PublisherClock> clocks_;
};

}  // namespace pbf_ros
