#include "pbf_ros/ros/SolidWrenchPublishers.h"

#include <algorithm>
#include <geometry_msgs/WrenchStamped.h>

namespace pbf_ros {

namespace {
geometry_msgs::Vector3 vector(const Eigen::Vector3d& v) {
  geometry_msgs::Vector3 out;
  out.x = v.x();
  out.y = v.y();
  out.z = v.z();
  return out;
}

void addScaled(pbf::Wrench& sum, const pbf::Wrench& w, double s) {
  sum.force += s * w.force;
  sum.torque += s * w.torque;
}
}  // namespace

SolidWrenchPublishers::SolidWrenchPublishers(ros::NodeHandle pnh, double rate, bool always_track)
    : pnh_(pnh), period_(1.0 / std::max(rate, 1e-3)), always_track_(always_track) {}

void SolidWrenchPublishers::setTargets(std::vector<WrenchTarget> targets) {
  topics_.clear();
  std::map<std::string, ros::Publisher> keep;
  for (WrenchTarget& t : targets) {
    auto found = publishers_.find(t.name);
    keep[t.name] = found != publishers_.end()
                       ? found->second
                       : pnh_.advertise<geometry_msgs::WrenchStamped>("wrench/" + t.name, 10);
    Topic topic;
    topic.target = std::move(t);
    topics_.push_back(std::move(topic));
  }
  for (auto& [name, pub] : publishers_)
    if (!keep.count(name)) pub.shutdown();
  publishers_ = std::move(keep);
  total_sum_ = pbf::Wrench();
  total_seconds_ = 0.0;
}

bool SolidWrenchPublishers::wanted() const {
  if (always_track_) return true;
  for (const auto& [name, pub] : publishers_)
    if (pub.getNumSubscribers() > 0) return true;
  return false;
}

void SolidWrenchPublishers::accumulate(const pbf::Scene& scene, const pbf::PbfSolver& solver,
                                       double dt) {
  const pbf::SolidWrenches& w = solver.wrenches();
  if (!w.valid || !(dt > 0.0)) return;
  for (Topic& t : topics_) {
    const Eigen::Isometry3d frame =
        targetFramePose(t.target, scene, solver.containerPose(), solver.obstacles());
    const pbf::Wrench local = targetWrench(t.target, w, solver.containerPose(), solver.obstacles(), frame);
    if (!local.allFinite()) continue;  // never published; the step's NaN guard reports
    addScaled(t.sum, local, dt);
    t.seconds += dt;
  }
  const pbf::Wrench total = totalWrench(w, solver.containerPose(), solver.obstacles());
  if (total.allFinite()) {
    addScaled(total_sum_, total, dt);
    total_seconds_ += dt;
  }
}

void SolidWrenchPublishers::publishDue(double wall, const ros::Time& stamp) {
  if (wall < next_wall_) return;
  next_wall_ = wall + period_;
  for (Topic& t : topics_) {
    const auto pub = publishers_.find(t.target.name);
    if (t.seconds > 0.0 && pub != publishers_.end() && pub->second.getNumSubscribers() > 0) {
      geometry_msgs::WrenchStamped msg;
      msg.header.stamp = stamp;
      msg.header.frame_id = t.target.frame;
      msg.wrench.force = vector(t.sum.force / t.seconds);
      msg.wrench.torque = vector(t.sum.torque / t.seconds);
      pub->second.publish(msg);
    }
    t.sum = pbf::Wrench();
    t.seconds = 0.0;
  }
}

bool SolidWrenchPublishers::takeTotal(pbf::Wrench& total) {
  if (!(total_seconds_ > 0.0)) return false;
  total.force = total_sum_.force / total_seconds_;
  total.torque = total_sum_.torque / total_seconds_;
  total_sum_ = pbf::Wrench();
  total_seconds_ = 0.0;
  return true;
}

}  // namespace pbf_ros
