// The robot's links as solids (issue 12, part 1): read the URDF from the parameter server at
// every rebuild, place each link's collision solids where tf says the link is, and append
// them to the scene's obstacles. From then on they are ordinary attached obstacles:
// TfAttachments moves them every step, SceneMarkers draws them in their link frames.
#include <map>
#include <set>

#include "pbf_ros/ros/FluidNode.h"
#include "pbf_ros/ros/RobotSource.h"

namespace pbf_ros {

namespace {
// Later rebuilds (reset, scene switch) find the tf buffer filled: a link still missing then
// is really missing, and the simulation thread should not stall long for it.
constexpr double kRebuildTfWait = 0.5;  // [wall s]
}  // namespace

std::vector<RobotLinkSolids> FluidNode::addRobotSolids(pbf::Scene& scene) {
  std::vector<RobotLinkSolids> links;
  if (!robot_source_.enabled()) return links;
  const RobotLoad load = loadRobot(robot_source_, nh_, scene.solver.particle_spacing,
                                   scene.solver.supportRadius());
  for (const std::string& problem : load.robot.problems)
    ROS_WARN("pbf_node: robot description %s: %s", load.param.c_str(), problem.c_str());
  if (load.robot.solids.empty()) {
    if (load.found)
      ROS_WARN("pbf_node: robot description %s gives no solids; the fluid runs without the robot",
               load.param.c_str());
    else if (!robot_links_.empty())  // silent only for a scene that never had a robot
      ROS_WARN("pbf_node: robot description %s is gone; the fluid is rebuilt without the robot",
               load.param.c_str());
    return links;
  }

  // Where each link is now. The first build waits for a robot_state_publisher that starts
  // alongside the node; a link tf does not know then is left out (its solids would otherwise
  // sit at the fluid_domain origin and carve a hole into the fluid).
  if (!attachments_) attachments_ = std::make_unique<TfAttachments>(domain_frame_);
  std::set<std::string> wanted;
  for (const UrdfSolid& s : load.robot.solids) wanted.insert(s.link);
  std::map<std::string, Eigen::Isometry3f> pose_of;
  const double wait = robot_built_once_ ? std::min(kRebuildTfWait, robot_source_.tf_wait)
                                        : robot_source_.tf_wait;
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(wait);
  while (true) {
    for (const std::string& link : wanted) {
      Eigen::Isometry3f pose;
      if (!pose_of.count(link) && attachments_->currentPose(link, pose)) pose_of[link] = pose;
    }
    if (pose_of.size() == wanted.size() || ros::WallTime::now() >= deadline || !ros::ok()) break;
    ros::WallDuration(0.02).sleep();
  }
  robot_built_once_ = true;

  std::size_t mesh_solids = 0;
  for (const std::string& link : wanted) {
    const auto pose = pose_of.find(link);
    RobotLinkSolids entry;
    entry.link = link;
    for (const UrdfSolid& s : load.robot.solids) {
      if (s.link != link) continue;
      if (pose == pose_of.end()) {
        ++entry.left_out;
        continue;
      }
      pbf::Obstacle o = s.obstacle;
      o.pose = pose->second * o.offset;  // so no fluid is seeded inside it
      entry.obstacles.push_back(scene.obstacles.size());
      scene.obstacles.push_back(o);
      mesh_solids += o.shape == pbf::Obstacle::Shape::Mesh ? 1 : 0;
    }
    if (entry.left_out > 0) {
      ROS_ERROR("pbf_node: robot link '%s' has no tf (%s -> %s) after %.1f s: its %zu solid(s) "
                "are left out until the next ~reset or scene switch",
                link.c_str(), domain_frame_.c_str(), link.c_str(), wait, entry.left_out);
      continue;
    }
    links.push_back(entry);
  }
  std::size_t taking_part = 0;
  for (const RobotLinkSolids& l : links) taking_part += l.obstacles.size();
  ROS_INFO("pbf_node: robot '%s' (%s): %zu solids on %zu links take part (%zu meshes, %.2f MiB "
           "of mesh grids), %zu problem(s)",
           load.robot.robot_name.c_str(), load.param.c_str(), taking_part, links.size(),
           mesh_solids, load.robot.sdfBytes() / 1048576.0, load.robot.problems.size());
  return links;
}

}  // namespace pbf_ros
