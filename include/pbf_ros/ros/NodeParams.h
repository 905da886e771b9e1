#pragma once
// The node's start-up settings of a fixed type, read so that a value of another type is an
// error naming the parameter. ros::NodeHandle::param keeps its default in silence when the
// type differs: start_paused:=maybe, or <param name="wrench_rate" value="1e-9"/>, which
// roslaunch passes on as a string (a helper probe: the node ran at 30 Hz without a word).

#include <sstream>
#include <stdexcept>
#include <string>

#include <ros/node_handle.h>
#include <xmlrpcpp/XmlRpcValue.h>

namespace pbf_ros {

// A parameter's value as a user wrote it, with its type: "1 (an integer)", not XML-RPC's
// "<value><i4>1</i4></value>".
inline std::string describeParam(const XmlRpc::XmlRpcValue& value) {
  std::ostringstream text;
  value.write(text);  // not <<: XmlRpcValue converts to several streamable types
  switch (value.getType()) {
    case XmlRpc::XmlRpcValue::TypeBoolean: {  // write() gives 1 or 0
      XmlRpc::XmlRpcValue copy = value;  // the conversion to bool is not const
      return std::string(static_cast<bool>(copy) ? "true" : "false") + " (a boolean)";
    }
    case XmlRpc::XmlRpcValue::TypeInt: return text.str() + " (an integer)";
    case XmlRpc::XmlRpcValue::TypeDouble: return text.str() + " (a number)";
    case XmlRpc::XmlRpcValue::TypeString: return "'" + text.str() + "' (a string)";
    case XmlRpc::XmlRpcValue::TypeArray: return text.str() + " (a list)";
    case XmlRpc::XmlRpcValue::TypeStruct: return text.str() + " (a map)";
    default: return text.str();
  }
}

// Each returns `fallback` when the parameter is not set and throws std::runtime_error when it
// is of another type.

// A boolean node setting; anything but true/false (e.g. start_paused:=maybe, which
// roslaunch passes as a string) is an error rather than silently false.
inline bool readBool(const ros::NodeHandle& nh, const std::string& name, bool fallback) {
  XmlRpc::XmlRpcValue value;
  if (!nh.getParam(name, value)) return fallback;
  if (value.getType() != XmlRpc::XmlRpcValue::TypeBoolean) {
    throw std::runtime_error("parameter ~" + name + ": expected true or false, got " + describeParam(value));
  }
  return static_cast<bool>(value);
}

// A numeric node setting (an integer is taken as a number too).
inline double readNumber(const ros::NodeHandle& nh, const std::string& name, double fallback) {
  XmlRpc::XmlRpcValue value;
  if (!nh.getParam(name, value)) return fallback;
  if (value.getType() == XmlRpc::XmlRpcValue::TypeDouble) return static_cast<double>(value);
  if (value.getType() == XmlRpc::XmlRpcValue::TypeInt) return static_cast<int>(value);
  throw std::runtime_error("parameter ~" + name + ": expected a number, got " + describeParam(value) +
                           " (in a launch file, <param type=\"double\">)");
}

// An integer node setting.
inline int readInteger(const ros::NodeHandle& nh, const std::string& name, int fallback) {
  XmlRpc::XmlRpcValue value;
  if (!nh.getParam(name, value)) return fallback;
  if (value.getType() == XmlRpc::XmlRpcValue::TypeInt) return static_cast<int>(value);
  throw std::runtime_error("parameter ~" + name + ": expected an integer, got " + describeParam(value));
}

// The checks below take a value already read and return what to use: the value, or
// `fallback` with `warning` set (naming ~name) for the caller to log. A start-up setting out
// of its range was taken in silence: max_lag -1 became 0.1 s, render_nice 100 became 19, a
// NaN diagnostics threshold never fired, a negative one fired on every error (a helper probe).

// A number in [lo, hi]; NaN is outside.
inline double withinRange(const std::string& name, double value, double lo, double hi, double fallback,
                          std::string& warning) {
  warning.clear();
  if (value >= lo && value <= hi) return value;
  std::ostringstream w;
  w << "~" << name << " " << value << " is not in [" << lo << ", " << hi << "]; using " << fallback;
  warning = w.str();
  return fallback;
}

// A frame id tf can use: not empty (tf2 and rviz cannot look up ""), not starting with '/'
// (tf2 refuses those).
inline std::string usableFrameId(const std::string& name, const std::string& value, const std::string& fallback,
                                 std::string& warning) {
  warning.clear();
  if (!value.empty() && value[0] != '/') return value;
  warning = "~" + name + " '" + value + "' is not a frame id tf can use (" +
            (value.empty() ? "empty" : "tf2 refuses a leading '/'") + "); using '" + fallback + "'";
  return fallback;
}

}  // namespace pbf_ros
