#include "pbf_ros/ros/TfStampGate.h"

namespace pbf_ros {

bool TfStampGate::admit(const std::string& child_frame, const ros::Time& stamp) {
  const auto [it, first] = last_.emplace(child_frame, stamp);
  if (first) return true;
  if (it->second == stamp) return false;
  it->second = stamp;
  return true;
}

}  // namespace pbf_ros
