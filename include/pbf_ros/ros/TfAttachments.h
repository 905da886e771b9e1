#pragma once
// Moves what a scene attaches to tf frames (its container, its obstacles) to where tf says
// those frames are, between steps. A frame moved by any node (a demo driver, a robot)
// then carries the solid, and the solid pushes the fluid.

#include <memory>
#include <string>
#include <vector>

#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "pbf_ros/core/PbfSolver.h"
#include "pbf_ros/core/Scene.h"

namespace pbf_ros {

class TfAttachments {
 public:
  explicit TfAttachments(std::string domain_frame);

  // True when the scene attaches anything to a tf frame (no tf work otherwise).
  static bool needed(const pbf::Scene& scene);

  // Sets the solver's container pose and obstacle poses from the latest transforms
  // (domain_frame <- frame). A frame tf does not know yet keeps its previous pose; the
  // names of such frames are returned so the caller can warn.
  std::vector<std::string> update(const pbf::Scene& scene, pbf::PbfSolver& solver);

 private:
  bool lookup(const std::string& frame, Eigen::Isometry3f& pose) const;

  std::string domain_frame_;
  std::unique_ptr<tf2_ros::Buffer> buffer_;
  std::unique_ptr<tf2_ros::TransformListener> listener_;  // created on first use
};

}  // namespace pbf_ros
