#include "pbf_ros/ros/RobotSource.h"

#include <stdexcept>

#include "pbf_ros/ros/NodeParams.h"

namespace pbf_ros {

namespace {
std::runtime_error wrongType(const std::string& name, const std::string& expected,
                             const XmlRpc::XmlRpcValue& value) {
  return std::runtime_error("parameter ~" + name + ": expected " + expected + ", got " + describeParam(value));
}
}  // namespace

RobotSource readRobotSource(const ros::NodeHandle& pnh) {
  RobotSource source;
  XmlRpc::XmlRpcValue value;
  if (pnh.getParam("robot_description_param", value)) {
    if (value.getType() != XmlRpc::XmlRpcValue::TypeString)
      throw wrongType("robot_description_param", "a parameter name (string)", value);
    source.description_param = static_cast<std::string>(value);
    source.param_named = true;
  }
  if (pnh.getParam("robot_links", value)) {
    if (value.getType() != XmlRpc::XmlRpcValue::TypeArray)
      throw wrongType("robot_links", "a list of link names", value);
    for (int i = 0; i < value.size(); ++i) {
      if (value[i].getType() != XmlRpc::XmlRpcValue::TypeString)
        throw wrongType("robot_links", "a list of link names (strings)", value);
      source.links.push_back(static_cast<std::string>(value[i]));
    }
  }
  if (pnh.getParam("robot_link_regex", value)) {
    if (value.getType() != XmlRpc::XmlRpcValue::TypeString)
      throw wrongType("robot_link_regex", "a regular expression (string)", value);
    source.link_regex = static_cast<std::string>(value);
  }
  if (pnh.getParam("robot_tf_wait", value)) {
    if (value.getType() == XmlRpc::XmlRpcValue::TypeDouble)
      source.tf_wait = static_cast<double>(value);
    else if (value.getType() == XmlRpc::XmlRpcValue::TypeInt)
      source.tf_wait = static_cast<int>(value);
    else
      throw wrongType("robot_tf_wait", "seconds (a number)", value);
    if (!(source.tf_wait >= 0.0 && source.tf_wait <= 600.0))
      throw std::runtime_error("parameter ~robot_tf_wait: expected 0 to 600 s");
  }
  return source;
}

RobotLoad loadRobot(const RobotSource& source, const ros::NodeHandle& nh, float spacing,
                    float support_radius) {
  RobotLoad load;
  if (!source.enabled()) return load;
  load.param = nh.resolveName(source.description_param);
  XmlRpc::XmlRpcValue value;
  if (!nh.getParam(source.description_param, value)) {
    // The default name absent is the common case of a scene without a robot.
    if (source.param_named)
      load.robot.problems.push_back("parameter " + load.param +
                                    " (~robot_description_param) is not set: no robot");
    return load;
  }
  if (value.getType() != XmlRpc::XmlRpcValue::TypeString) {
    load.robot.problems.push_back("parameter " + load.param +
                                  " is not a string (expected the URDF's XML): no robot");
    return load;
  }
  load.found = true;
  UrdfSolidsOptions options;
  options.links = source.links;
  options.link_regex = source.link_regex;
  options.sdf.cell = 0.5f * spacing;
  options.sdf.band = support_radius + spacing;
  load.robot = urdfSolids(static_cast<std::string>(value), options);
  return load;
}

}  // namespace pbf_ros
