#include "pbf_ros/ros/ObstacleMover.h"
#include "pbf_ros/ros/EchoedText.h"
#include "pbf_ros/ros/SceneMarkers.h"
#include "pbf_ros/ros/WallThrottle.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <visualization_msgs/InteractiveMarker.h>
#include <visualization_msgs/InteractiveMarkerControl.h>
#include <visualization_msgs/InteractiveMarkerFeedback.h>

namespace pbf_ros {

namespace {

constexpr double kMarkerUpdatePeriod = 0.1;  // [wall s] between handle pose updates

std::string nameOf(std::size_t index) { return "obstacle_" + std::to_string(index); }

// Six controls (move and rotate about x, y, z) and a translucent handle as large as the
// obstacle's bounding sphere, which rviz lets the user drag freely in the view plane.
visualization_msgs::InteractiveMarker dragMarker(const pbf::Obstacle& o, std::size_t index,
                                                 const std::string& frame) {
  visualization_msgs::InteractiveMarker m;
  m.header.frame_id = frame;
  m.name = nameOf(index);
  m.description = "drag " + m.name;
  m.pose = poseMsg(o.pose);
  const float radius = o.boundingRadius();
  m.scale = 2.2f * radius;
  visualization_msgs::InteractiveMarkerControl handle;
  handle.name = "move_3d";
  handle.interaction_mode = visualization_msgs::InteractiveMarkerControl::MOVE_3D;
  handle.always_visible = true;
  visualization_msgs::Marker sphere;
  sphere.type = visualization_msgs::Marker::SPHERE;
  sphere.scale.x = sphere.scale.y = sphere.scale.z = 2.0 * radius;
  sphere.color.r = 0.3f;
  sphere.color.g = 0.6f;
  sphere.color.b = 1.0f;
  sphere.color.a = 0.25f;
  sphere.pose.orientation.w = 1.0;
  handle.markers.push_back(sphere);
  m.controls.push_back(handle);
  const char* axes[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    visualization_msgs::InteractiveMarkerControl c;
    // The control's orientation turns its x axis onto the axis it acts along.
    c.orientation.w = 1.0;
    if (a == 1) c.orientation.z = 1.0;
    if (a == 2) c.orientation.y = 1.0;
    const double norm = std::sqrt(c.orientation.w * c.orientation.w + c.orientation.y * c.orientation.y +
                                  c.orientation.z * c.orientation.z);
    c.orientation.w /= norm;
    c.orientation.y /= norm;
    c.orientation.z /= norm;
    c.name = std::string("move_") + axes[a];
    c.interaction_mode = visualization_msgs::InteractiveMarkerControl::MOVE_AXIS;
    m.controls.push_back(c);
    c.name = std::string("rotate_") + axes[a];
    c.interaction_mode = visualization_msgs::InteractiveMarkerControl::ROTATE_AXIS;
    m.controls.push_back(c);
  }
  return m;
}

}  // namespace

Eigen::Isometry3f stepToward(const Eigen::Isometry3f& current, const Eigen::Isometry3f& target,
                             float max_move, float radius) {
  // In double: a target far out (any finite float) has a distance whose square overflows
  // a float, which made the step's fraction 0 and left the obstacle where it was.
  const Eigen::Vector3d shift = (target.translation() - current.translation()).cast<double>();
  const Eigen::Quaternionf from(current.linear()), to(target.linear());
  const double angle = from.angularDistance(to);
  const double move = shift.norm() + angle * radius;  // bound on any point's travel
  if (!(move > max_move)) return target;
  const double f = max_move / move;
  Eigen::Isometry3f step = Eigen::Isometry3f::Identity();
  step.linear() = from.slerp(static_cast<float>(f), to).normalized().toRotationMatrix();
  step.translation() = current.translation() + (f * shift).cast<float>();
  return step;
}

bool poseFromMsg(const geometry_msgs::Pose& msg, Eigen::Isometry3f& pose, std::string& why) {
  const auto& p = msg.position;
  const auto& o = msg.orientation;
  const double values[7] = {p.x, p.y, p.z, o.x, o.y, o.z, o.w};
  for (double v : values) {
    // A double beyond float range is as unusable as a NaN: the solver works in float.
    if (!std::isfinite(v) || !std::isfinite(static_cast<float>(v))) {
      std::ostringstream m;
      m << (std::isfinite(v) ? "a pose beyond float range, which the solver works in" : "non-finite pose")
        << " (position [" << p.x << ", " << p.y << ", " << p.z << "], orientation ["
        << o.x << ", " << o.y << ", " << o.z << ", " << o.w << "])";
      why = m.str();
      return false;
    }
  }
  const Eigen::Quaterniond q(o.w, o.x, o.y, o.z);
  if (q.norm() < 1e-6) {
    why = "orientation is not a rotation (a zero quaternion)";
    return false;
  }
  pose = Eigen::Translation3f(Eigen::Vector3d(p.x, p.y, p.z).cast<float>()) *
         q.normalized().cast<float>();
  return true;
}

ObstacleMover::ObstacleMover(ros::NodeHandle private_nh, std::string domain_frame, FramePose frame_pose)
    : pnh_(private_nh),
      domain_frame_(std::move(domain_frame)),
      frame_pose_(std::move(frame_pose)),
      server_(private_nh.resolveName("obstacle_markers")) {}

std::vector<std::size_t> ObstacleMover::freeObstacles() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return free_;
}

void ObstacleMover::setScene(const pbf::Scene& scene, const std::vector<std::size_t>& robot_obstacles) {
  std::vector<std::size_t> movable;
  for (std::size_t k = 0; k < scene.obstacles.size(); ++k) {
    const bool robot = std::find(robot_obstacles.begin(), robot_obstacles.end(), k) != robot_obstacles.end();
    if (scene.obstacles[k].frame.empty() && !scene.floats(k) && !robot) movable.push_back(k);
  }
  std::uint64_t generation;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    generation = ++generation_;
    free_ = movable;
    targets_.clear();
  }
  subscribers_.clear();
  server_.clear();
  for (std::size_t k : movable) {
    server_.insert(dragMarker(scene.obstacles[k], k, domain_frame_),
                   [this](const visualization_msgs::InteractiveMarkerFeedbackConstPtr& f) { onFeedback(f); });
    subscribers_.push_back(pnh_.subscribe<geometry_msgs::PoseStamped>(
        "obstacle_pose/" + nameOf(k), 10,
        [this, k, generation](const geometry_msgs::PoseStamped::ConstPtr& msg) {
          request(k, generation, msg->header.frame_id, msg->pose,
                  pnh_.resolveName("obstacle_pose/" + nameOf(k)));
        }));
  }
  server_.applyChanges();
}

void ObstacleMover::onFeedback(const visualization_msgs::InteractiveMarkerFeedbackConstPtr& f) {
  if (f->event_type != visualization_msgs::InteractiveMarkerFeedback::POSE_UPDATE &&
      f->event_type != visualization_msgs::InteractiveMarkerFeedback::MOUSE_UP)
    return;
  const std::string prefix = "obstacle_";
  if (f->marker_name.compare(0, prefix.size(), prefix) != 0) return;
  std::size_t index = 0;
  try {
    index = std::stoul(f->marker_name.substr(prefix.size()));
  } catch (const std::exception&) {
    return;
  }
  std::uint64_t generation;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    generation = generation_;
  }
  request(index, generation, f->header.frame_id, f->pose, "interactive marker " + f->marker_name);
}

void ObstacleMover::request(std::size_t index, std::uint64_t generation, const std::string& frame,
                            const geometry_msgs::Pose& msg, const std::string& source) {
  Eigen::Isometry3f pose;
  std::string why;
  if (!poseFromMsg(msg, pose, why)) {
    PBF_WARN_THROTTLE(2.0, "pbf_node: %s: refused %s; obstacle_%zu stays where it is", source.c_str(),
                      why.c_str(), index);
    return;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  if (generation != generation_) return;  // meant for a scene that is gone
  if (std::find(free_.begin(), free_.end(), index) == free_.end()) {
    PBF_WARN_THROTTLE(2.0, "pbf_node: %s: obstacle_%zu cannot be moved (it is not a free obstacle "
                      "of this scene)", source.c_str(), index);
    return;
  }
  targets_[index] = Target{pose, frame == domain_frame_ ? std::string() : frame};
}

bool ObstacleMover::apply(pbf::PbfSolver& solver, pbf::Scene& scene) {
  std::map<std::size_t, Target> targets;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    targets = targets_;
  }
  if (targets.empty()) return false;
  const float max_move = 0.5f * solver.params().particle_spacing;
  std::vector<std::size_t> arrived;
  bool moved = false;
  for (const auto& [k, target] : targets) {
    if (k >= solver.obstacles().size() || k >= scene.obstacles.size()) {
      arrived.push_back(k);
      continue;
    }
    Eigen::Isometry3f goal = target.pose;
    if (!target.frame.empty()) {
      Eigen::Isometry3f frame;
      if (!frame_pose_(target.frame, frame)) {
        PBF_WARN_THROTTLE(2.0, "pbf_node: obstacle_%zu: no tf from %s to '%s'; the move is dropped", k,
                          domain_frame_.c_str(), echoed(target.frame).c_str());
        arrived.push_back(k);
        continue;
      }
      goal = frame * target.pose;
    }
    // Allowed (lifting a solid out of the water is a move too), but said: a typo sends it away.
    if (!solver.container().isEmpty() &&
        !solver.container().contains(solver.containerPose().inverse() * goal.translation())) {
      PBF_WARN_THROTTLE(10.0, "pbf_node: obstacle_%zu: its target (%g, %g, %g) in %s is outside the "
                        "container; it leaves the fluid", k, goal.translation().x(), goal.translation().y(),
                        goal.translation().z(), domain_frame_.c_str());
    }
    const pbf::Obstacle& o = solver.obstacles()[k];
    const Eigen::Isometry3f next = stepToward(o.pose, goal, max_move, o.boundingRadius());
    if (!next.matrix().allFinite()) {  // cannot happen with finite input; be sure
      arrived.push_back(k);
      continue;
    }
    solver.setObstaclePose(k, next);
    scene.obstacles[k].pose = next;
    moved = true;
    if (next.isApprox(goal, 1e-6f)) arrived.push_back(k);
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (std::size_t k : arrived) {
      const auto it = targets_.find(k);
      // A newer request may have replaced the target meanwhile: keep that one.
      if (it != targets_.end() && it->second.pose.isApprox(targets.at(k).pose) &&
          it->second.frame == targets.at(k).frame)
        targets_.erase(it);
    }
  }
  // The handles follow (not every step: rviz needs no more than a few updates a second).
  const ros::WallTime now = ros::WallTime::now();
  if (moved && ((now - last_marker_update_).toSec() >= kMarkerUpdatePeriod || !arrived.empty())) {
    last_marker_update_ = now;
    for (const auto& [k, target] : targets)
      if (k < scene.obstacles.size()) server_.setPose(nameOf(k), poseMsg(scene.obstacles[k].pose));
    server_.applyChanges();
  }
  return moved;
}

}  // namespace pbf_ros
