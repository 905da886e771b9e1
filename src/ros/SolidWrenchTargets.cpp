#include "pbf_ros/ros/SolidWrenchTargets.h"

#include <cctype>
#include <set>

namespace pbf_ros {

std::string topicSafeName(const std::string& name) {
  std::string out;
  for (char c : name) out += std::isalnum(static_cast<unsigned char>(c)) || c == '_' ? c : '_';
  if (out.empty() || !std::isalpha(static_cast<unsigned char>(out[0]))) out = "s_" + out;
  return out;
}

std::vector<WrenchTarget> wrenchTargets(const pbf::Scene& scene,
                                        const std::vector<RobotLinkSolids>& robot_links,
                                        const std::string& domain_frame) {
  std::vector<WrenchTarget> targets;
  std::set<std::string> taken;
  auto add = [&](WrenchTarget t) {
    const std::string base = t.name;
    for (int k = 2; !taken.insert(t.name).second; ++k) t.name = base + "_" + std::to_string(k);
    targets.push_back(std::move(t));
  };
  WrenchTarget container;
  container.name = "container";
  container.frame = scene.container_frame.empty() ? domain_frame : scene.container_frame;
  container.container = true;
  add(container);
  std::set<std::size_t> robot;
  for (const RobotLinkSolids& l : robot_links) robot.insert(l.obstacles.begin(), l.obstacles.end());
  for (std::size_t k = 0; k < scene.obstacles.size(); ++k) {
    if (robot.count(k)) continue;
    WrenchTarget t;
    t.name = "obstacle_" + std::to_string(k);
    t.frame = scene.obstacles[k].frame.empty() ? domain_frame : scene.obstacles[k].frame;
    t.obstacles = {k};
    add(t);
  }
  for (const RobotLinkSolids& l : robot_links) {
    if (l.obstacles.empty()) continue;
    WrenchTarget t;
    t.name = topicSafeName(l.link);
    t.frame = l.link;
    t.obstacles = l.obstacles;
    add(t);
  }
  return targets;
}

Eigen::Isometry3d targetFramePose(const WrenchTarget& target, const pbf::Scene& scene,
                                  const Eigen::Isometry3f& container_pose,
                                  const std::vector<pbf::Obstacle>& obstacles) {
  if (target.container)
    return scene.container_frame.empty() ? Eigen::Isometry3d::Identity() : container_pose.cast<double>();
  if (target.obstacles.empty() || target.obstacles[0] >= obstacles.size())
    return Eigen::Isometry3d::Identity();
  const pbf::Obstacle& o = obstacles[target.obstacles[0]];
  if (o.frame.empty()) return Eigen::Isometry3d::Identity();
  return o.pose.cast<double>() * o.offset.cast<double>().inverse(Eigen::Isometry);
}

namespace {
// Torque about the fluid_domain origin from one about `origin`.
pbf::Wrench aboutDomainOrigin(const pbf::Wrench& w, const Eigen::Vector3f& origin) {
  return w.movedTo(origin.cast<double>(), Eigen::Vector3d::Zero());
}
}  // namespace

pbf::Wrench targetWrench(const WrenchTarget& target, const pbf::SolidWrenches& wrenches,
                         const Eigen::Isometry3f& container_pose,
                         const std::vector<pbf::Obstacle>& obstacles,
                         const Eigen::Isometry3d& frame) {
  pbf::Wrench sum;  // in fluid_domain, about its origin
  if (target.container) sum += aboutDomainOrigin(wrenches.container, container_pose.translation());
  for (std::size_t k : target.obstacles)
    if (k < wrenches.obstacles.size() && k < obstacles.size())
      sum += aboutDomainOrigin(wrenches.obstacles[k], obstacles[k].pose.translation());
  const pbf::Wrench at_frame = sum.movedTo(Eigen::Vector3d::Zero(), frame.translation());
  const Eigen::Matrix3d to_frame = frame.linear().transpose();
  pbf::Wrench local;
  local.force = to_frame * at_frame.force;
  local.torque = to_frame * at_frame.torque;
  return local;
}

pbf::Wrench totalWrench(const pbf::SolidWrenches& wrenches, const Eigen::Isometry3f& container_pose,
                        const std::vector<pbf::Obstacle>& obstacles) {
  pbf::Wrench sum = aboutDomainOrigin(wrenches.container, container_pose.translation());
  for (std::size_t k = 0; k < wrenches.obstacles.size() && k < obstacles.size(); ++k)
    sum += aboutDomainOrigin(wrenches.obstacles[k], obstacles[k].pose.translation());
  return sum;
}

}  // namespace pbf_ros
