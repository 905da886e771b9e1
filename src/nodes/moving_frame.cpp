// moving_frame: publishes a tf frame that moves, to carry a scene's container or obstacles
// (demos: launch/sloshing.launch, launch/pouring.launch). Runs on ROS time, so with
// pbf_node's ~publish_clock the motion follows simulated time even when the simulation
// runs slower than real time.
//
// Parameters (private):
//   parent_frame (fluid_domain), child_frame (required)
//   motion: "oscillate" -- translation amplitude * sin(2 pi t / period) along axis;
//           the amplitude ramps up over the first period so the start is smooth
//         | "tilt"      -- rotation about axis through pivot, from 0 to angle over duration
//           (smooth start and stop), then held
//   axis [x, y, z] (unit-normalised), amplitude [m], period [s], pivot [x, y, z] [m],
//   angle [rad], duration [s], start_delay [s] (motion starts after it), rate [Hz]
#include <cmath>
#include <string>
#include <vector>

#include <geometry_msgs/TransformStamped.h>
#include <ros/ros.h>
#include <tf2/LinearMath/Quaternion.h>
#include <tf2/LinearMath/Transform.h>
#include <tf2_ros/transform_broadcaster.h>

namespace {

tf2::Vector3 readVector(ros::NodeHandle& nh, const std::string& name, tf2::Vector3 fallback) {
  std::vector<double> v;
  if (!nh.getParam(name, v)) return fallback;
  if (v.size() != 3 || !std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) {
    ROS_WARN("moving_frame: ~%s must be a list of 3 finite numbers; using the default", name.c_str());
    return fallback;
  }
  return tf2::Vector3(v[0], v[1], v[2]);
}

double smoothstep(double x) {
  x = std::min(1.0, std::max(0.0, x));
  return x * x * (3.0 - 2.0 * x);
}

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "moving_frame");
  ros::NodeHandle pnh("~");
  std::string parent, child, motion;
  pnh.param<std::string>("parent_frame", parent, "fluid_domain");
  pnh.param<std::string>("child_frame", child, "");
  pnh.param<std::string>("motion", motion, "oscillate");
  if (child.empty() || (motion != "oscillate" && motion != "tilt")) {
    ROS_FATAL("moving_frame: needs ~child_frame and ~motion 'oscillate' or 'tilt' (got '%s')",
              motion.c_str());
    return 1;
  }
  tf2::Vector3 axis = readVector(pnh, "axis", tf2::Vector3(1, 0, 0));
  if (axis.length() < 1e-9) axis = tf2::Vector3(1, 0, 0);
  axis.normalize();
  const tf2::Vector3 pivot = readVector(pnh, "pivot", tf2::Vector3(0, 0, 0));
  const double amplitude = pnh.param("amplitude", 0.05);
  const double period = std::max(1e-3, pnh.param("period", 1.0));
  const double angle = pnh.param("angle", 1.5);
  const double duration = std::max(1e-3, pnh.param("duration", 3.0));
  const double start_delay = std::max(0.0, pnh.param("start_delay", 0.5));
  const double rate = std::max(1.0, pnh.param("rate", 60.0));

  ros::Time::waitForValid();  // with use_sim_time: until the first /clock
  const ros::Time start = ros::Time::now();
  tf2_ros::TransformBroadcaster broadcaster;
  ros::Rate loop(rate);
  ros::Time last_stamp;
  while (ros::ok()) {
    // On simulated time the clock may not have moved since the last pose: tf2 rejects a
    // repeated stamp, so wait for the next tick instead.
    const ros::Time now = ros::Time::now();
    if (now == last_stamp) {
      ros::spinOnce();
      loop.sleep();
      continue;
    }
    last_stamp = now;
    const double t = std::max(0.0, (now - start).toSec() - start_delay);
    tf2::Transform pose = tf2::Transform::getIdentity();
    if (motion == "oscillate") {
      const double ramp = std::min(1.0, t / period);
      pose.setOrigin(axis * (ramp * amplitude * std::sin(2.0 * M_PI * t / period)));
    } else {
      const tf2::Quaternion q(axis, angle * smoothstep(t / duration));
      // Rotation about an axis through the pivot: p -> pivot + R (p - pivot).
      pose.setRotation(q);
      pose.setOrigin(pivot - tf2::quatRotate(q, pivot));
    }
    geometry_msgs::TransformStamped msg;
    msg.header.stamp = now;
    msg.header.frame_id = parent;
    msg.child_frame_id = child;
    msg.transform.translation.x = pose.getOrigin().x();
    msg.transform.translation.y = pose.getOrigin().y();
    msg.transform.translation.z = pose.getOrigin().z();
    msg.transform.rotation.x = pose.getRotation().x();
    msg.transform.rotation.y = pose.getRotation().y();
    msg.transform.rotation.z = pose.getRotation().z();
    msg.transform.rotation.w = pose.getRotation().w();
    broadcaster.sendTransform(msg);
    ros::spinOnce();
    loop.sleep();
  }
  return 0;
}
