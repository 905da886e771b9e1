#include "pbf_ros/ros/TfAttachments.h"

#include <algorithm>
#include <cmath>
#include <tf2/exceptions.h>

namespace pbf_ros {

namespace {
// Missing frames are not reported during this long after a (re)start [wall s].
constexpr double kMissingGrace = 3.0;
// A publisher whose next pose is later than this is reported as behind [simulated s].
constexpr double kOverdue = 0.25;
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

void TfAttachments::restart() {
  started_ = ros::WallTime::now();
  clocks_.clear();  // the publishers start again with the simulation
}

TfAttachments::Lookup TfAttachments::lookup(const std::string& frame, const ros::Time& time,
                                           double max_wait, Eigen::Isometry3f& pose, double* behind) {
  geometry_msgs::TransformStamped t;
  try {
    if (!buffer_->_frameExists(frame)) return Lookup::kUnknown;
    t = buffer_->lookupTransform(domain_frame_, frame, ros::Time(0));  // latest
    const ros::Time latest = t.header.stamp;
    PublisherClock& clock = clocks_[frame];
    if (latest != clock.latest) clock.previous = clock.latest, clock.latest = latest;
    if (!time.isZero() && time != latest && !latest.isZero()) {
      // Interpolate at the step's time. A publisher behind the step is waited for (bounded)
      // only when its next pose is due: its latest stamp plus its interval. Between two of
      // its poses a wait cannot help, since on the node's /clock it sends the next one only
      // once the simulation gets there; a pouring cup's five boxes on a 60 Hz frame made the
      // steps between its poses wait 5 x 20 ms each (real-time factor 0.05).
      bool ready = buffer_->canTransform(domain_frame_, frame, time);
      // In seconds: ros::Time differences throw beyond 2^31 s (a hostile /clock).
      const double now_s = time.toSec(), latest_s = latest.toSec(), previous_s = clock.previous.toSec();
      const bool interval_known = !clock.previous.isZero() && previous_s < latest_s;
      const bool due = !interval_known || now_s >= latest_s + (latest_s - previous_s);
      if (!ready && time > latest && due && clock.waited_in_vain != latest) {
        const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(max_wait);
        while (!ready && ros::WallTime::now() < deadline) {
          ros::WallDuration(0.0005).sleep();
          ready = buffer_->canTransform(domain_frame_, frame, time);
        }
        if (!ready) clock.waited_in_vain = latest;  // not again until it sends a newer pose
      }
      // Overdue by more than scheduling jitter (a 60 Hz publisher answering a /clock a few ms
      // late): its solid holds a pose that is getting old.
      const double overdue = now_s - latest_s - (interval_known ? latest_s - previous_s : 0.0);
      if (!ready && behind != nullptr && overdue > kOverdue) *behind = now_s - latest_s;
      if (ready) t = buffer_->lookupTransform(domain_frame_, frame, time);
    }
  } catch (const tf2::TransformException&) {
    return Lookup::kUnknown;
  }
  const auto& r = t.transform.rotation;
  const auto& p = t.transform.translation;
  const Eigen::Quaternionf q(static_cast<float>(r.w), static_cast<float>(r.x),
                             static_cast<float>(r.y), static_cast<float>(r.z));
  if (!std::isfinite(q.norm()) || q.norm() < 1e-6f) return Lookup::kNonFinite;
  const Eigen::Isometry3f found = Eigen::Translation3f(static_cast<float>(p.x), static_cast<float>(p.y),
                                                       static_cast<float>(p.z)) *
                                  q.normalized();
  if (!found.matrix().allFinite()) return Lookup::kNonFinite;
  pose = found;
  return Lookup::kFound;
}

bool TfAttachments::currentPose(const std::string& frame, Eigen::Isometry3f& pose) {
  listen();
  return lookup(frame, ros::Time(0), 0.0, pose) == Lookup::kFound;
}

TfAttachments::Report TfAttachments::update(const pbf::Scene& scene, pbf::PbfSolver& solver,
                                            const ros::Time& time, double max_wait) {
  Report report;
  if (!needed(scene)) return report;
  listen();
  // Each frame once per step, however many solids it carries (a cup is five boxes).
  struct Found {
    Lookup result;
    Eigen::Isometry3f pose;
  };
  std::map<std::string, Found> found;
  auto poseOf = [&](const std::string& frame) -> const Found& {
    auto it = found.find(frame);
    if (it != found.end()) return it->second;
    Found f{Lookup::kUnknown, Eigen::Isometry3f::Identity()};
    double behind = -1.0;
    f.result = lookup(frame, time, max_wait, f.pose, &behind);
    if (f.result == Lookup::kUnknown) report.missing.push_back(frame);
    if (f.result == Lookup::kNonFinite) report.non_finite.push_back(frame);
    if (behind >= 0.0) report.behind.emplace_back(frame, behind);
    return found.emplace(frame, f).first->second;
  };
  if (!scene.container_frame.empty()) {
    const Found& f = poseOf(scene.container_frame);
    if (f.result == Lookup::kFound) solver.setContainerPose(f.pose);
  }
  const std::size_t n = std::min(scene.obstacles.size(), solver.obstacles().size());
  for (std::size_t k = 0; k < n; ++k) {
    const pbf::Obstacle& o = scene.obstacles[k];
    if (o.frame.empty() || scene.floats(k)) continue;
    const Found& f = poseOf(o.frame);
    if (f.result == Lookup::kFound) solver.setObstaclePose(k, f.pose * o.offset);
  }
  if ((ros::WallTime::now() - started_).toSec() < kMissingGrace) report.missing.clear();
  return report;
}

}  // namespace pbf_ros
