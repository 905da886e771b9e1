#include "pbf_ros/ros/TfAttachments.h"

#include <algorithm>
#include <tf2/exceptions.h>

namespace pbf_ros {

TfAttachments::TfAttachments(std::string domain_frame) : domain_frame_(std::move(domain_frame)) {}

bool TfAttachments::needed(const pbf::Scene& scene) {
  return !scene.container_frame.empty() ||
         std::any_of(scene.obstacles.begin(), scene.obstacles.end(),
                     [](const pbf::Obstacle& o) { return !o.frame.empty(); });
}

bool TfAttachments::lookup(const std::string& frame, Eigen::Isometry3f& pose) const {
  geometry_msgs::TransformStamped t;
  try {
    t = buffer_->lookupTransform(domain_frame_, frame, ros::Time(0));  // latest
  } catch (const tf2::TransformException&) {
    return false;
  }
  const auto& r = t.transform.rotation;
  const auto& p = t.transform.translation;
  const Eigen::Quaternionf q(static_cast<float>(r.w), static_cast<float>(r.x),
                             static_cast<float>(r.y), static_cast<float>(r.z));
  if (!std::isfinite(q.norm()) || q.norm() < 1e-6f) return false;
  pose = Eigen::Translation3f(static_cast<float>(p.x), static_cast<float>(p.y),
                              static_cast<float>(p.z)) *
         q.normalized();
  return pose.matrix().allFinite();
}

std::vector<std::string> TfAttachments::update(const pbf::Scene& scene, pbf::PbfSolver& solver) {
  std::vector<std::string> missing;
  if (!needed(scene)) return missing;
  if (!listener_) {  // subscribe to /tf only once a scene needs it
    buffer_ = std::make_unique<tf2_ros::Buffer>();
    listener_ = std::make_unique<tf2_ros::TransformListener>(*buffer_);
  }
  Eigen::Isometry3f pose;
  if (!scene.container_frame.empty()) {
    if (lookup(scene.container_frame, pose))
      solver.setContainerPose(pose);
    else
      missing.push_back(scene.container_frame);
  }
  const std::size_t n = std::min(scene.obstacles.size(), solver.obstacles().size());
  for (std::size_t k = 0; k < n; ++k) {
    const pbf::Obstacle& o = scene.obstacles[k];
    if (o.frame.empty()) continue;
    if (lookup(o.frame, pose))
      solver.setObstaclePose(k, pose * o.offset);
    else if (std::find(missing.begin(), missing.end(), o.frame) == missing.end())
      missing.push_back(o.frame);
  }
  return missing;
}

}  // namespace pbf_ros
