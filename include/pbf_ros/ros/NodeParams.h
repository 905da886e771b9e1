#pragma once
// The node's start-up settings of a fixed type, read so that a value of another type is an
// error naming the parameter. ros::NodeHandle::param keeps its default in silence when the
// type differs: start_paused:=maybe, or <param name="wrench_rate" value="1e-9"/>, which
// roslaunch passes on as a string (a helper probe: the node ran at 30 Hz without a word).

#include <stdexcept>
#include <string>

#include <ros/node_handle.h>
#include <xmlrpcpp/XmlRpcValue.h>

namespace pbf_ros {

// Each returns `fallback` when the parameter is not set and throws std::runtime_error when it
// is of another type.

// A boolean node setting; anything but true/false (e.g. start_paused:=maybe, which
// roslaunch passes as a string) is an error rather than silently false.
inline bool readBool(const ros::NodeHandle& nh, const std::string& name, bool fallback) {
  XmlRpc::XmlRpcValue value;
  if (!nh.getParam(name, value)) return fallback;
  if (value.getType() != XmlRpc::XmlRpcValue::TypeBoolean) {
    throw std::runtime_error("parameter ~" + name + ": expected true or false, got " +
                             value.toXml());
  }
  return static_cast<bool>(value);
}

// A numeric node setting (an integer is taken as a number too).
inline double readNumber(const ros::NodeHandle& nh, const std::string& name, double fallback) {
  XmlRpc::XmlRpcValue value;
  if (!nh.getParam(name, value)) return fallback;
  if (value.getType() == XmlRpc::XmlRpcValue::TypeDouble) return static_cast<double>(value);
  if (value.getType() == XmlRpc::XmlRpcValue::TypeInt) return static_cast<int>(value);
  throw std::runtime_error("parameter ~" + name + ": expected a number, got " + value.toXml() +
                           " (in a launch file, <param type=\"double\">)");
}

// An integer node setting.
inline int readInteger(const ros::NodeHandle& nh, const std::string& name, int fallback) {
  XmlRpc::XmlRpcValue value;
  if (!nh.getParam(name, value)) return fallback;
  if (value.getType() == XmlRpc::XmlRpcValue::TypeInt) return static_cast<int>(value);
  throw std::runtime_error("parameter ~" + name + ": expected an integer, got " + value.toXml());
}

}  // namespace pbf_ros
