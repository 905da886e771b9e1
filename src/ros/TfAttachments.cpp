#include "pbf_ros/ros/TfAttachments.h"

#include <algorithm>
#include <tf2/exceptions.h>

namespace pbf_ros {

namespace {
// Missing frames are not reported during this long after a (re)start [wall s].
constexpr double kMissingGrace = 3.0;
}  // namespace

TfAttachments::TfAttachments(std::string domain_frame)
    : domain_frame_(std::move(domain_frame)), started_(ros::WallTime::now()) {}

bool TfAttachments::needed(const pbf::Scene& scene) {
  return !scene.container_frame.empty() ||
         [&scene] {  // floating obstacles' frames are published by the node, not read
           for (std::size_t k = 0; k < scene.obstacles.size(); ++k)
             if (!scene.obstacles[k].frame.empty() && !scene.floats(k)) return true;
           return false;
         }() ||
         std::any_of(scene.fluid.begin(), scene.fluid.end(),
                     [](const pbf::FluidBlock& b) { return !b.frame.empty(); });
}

TfAttachments::TfAttachments(std::string domain_frame, std::shared_ptr<tf2_ros::Buffer> buffer)
    : domain_frame_(std::move(domain_frame)), started_(ros::WallTime::now()), buffer_(std::move(buffer)) {}

void TfAttachments::listen() {
  if (buffer_) return;
  buffer_ = std::make_shared<tf2_ros::Buffer>();
  listener_ = std::make_unique<tf2_ros::TransformListener>(*buffer_);
}

void TfAttachments::restart() { started_ = ros::WallTime::now(); }

bool TfAttachments::lookup(const std::string& frame, const ros::Time& time, double max_wait,
                           Eigen::Isometry3f& pose) const {
  geometry_msgs::TransformStamped t;
  try {
    if (!buffer_->_frameExists(frame)) return false;
    t = buffer_->lookupTransform(domain_frame_, frame, ros::Time(0));  // latest
    if (!time.isZero() && time != t.header.stamp && !t.header.stamp.isZero()) {
      // Interpolate at the step's time; wait (bounded) for a publisher that is behind.
      const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(max_wait);
      bool ready = buffer_->canTransform(domain_frame_, frame, time);
      while (!ready && time > t.header.stamp && ros::WallTime::now() < deadline) {
        ros::WallDuration(0.0005).sleep();
        ready = buffer_->canTransform(domain_frame_, frame, time);
      }
      if (ready) t = buffer_->lookupTransform(domain_frame_, frame, time);
    }
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

bool TfAttachments::currentPose(const std::string& frame, Eigen::Isometry3f& pose) {
  listen();
  return lookup(frame, ros::Time(0), 0.0, pose);
}

std::vector<std::string> TfAttachments::update(const pbf::Scene& scene, pbf::PbfSolver& solver,
                                               const ros::Time& time, double max_wait) {
  std::vector<std::string> missing;
  if (!needed(scene)) return missing;
  listen();
  Eigen::Isometry3f pose;
  if (!scene.container_frame.empty()) {
    if (lookup(scene.container_frame, time, max_wait, pose))
      solver.setContainerPose(pose);
    else
      missing.push_back(scene.container_frame);
  }
  const std::size_t n = std::min(scene.obstacles.size(), solver.obstacles().size());
  for (std::size_t k = 0; k < n; ++k) {
    const pbf::Obstacle& o = scene.obstacles[k];
    if (o.frame.empty() || scene.floats(k)) continue;
    if (lookup(o.frame, time, max_wait, pose))
      solver.setObstaclePose(k, pose * o.offset);
    else if (std::find(missing.begin(), missing.end(), o.frame) == missing.end())
      missing.push_back(o.frame);
  }
  if ((ros::WallTime::now() - started_).toSec() < kMissingGrace) missing.clear();
  return missing;
}

}  // namespace pbf_ros
