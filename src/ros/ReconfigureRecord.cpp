#include "pbf_ros/ros/ReconfigureRecord.h"

namespace pbf_ros {

ReconfigureRecord::ReconfigureRecord(const ros::NodeHandle& private_nh)
    : nh_(private_nh),
      written_nh_(private_nh, std::string(kKey) + "/written"),
      user_nh_(private_nh, std::string(kKey) + "/user") {}

std::set<std::string> ReconfigureRecord::forgetPreviousRun() const {
  std::set<std::string> forgotten;
  for (const auto& desc : FluidConfig::__getParamDescriptions__()) {
    XmlRpc::XmlRpcValue current, written, user;
    if (!nh_.getParam(desc->name, current) || !written_nh_.getParam(desc->name, written)) continue;
    if (!(current == written)) continue;  // set by someone else since the last run wrote it
    if (user_nh_.getParam(desc->name, user))
      nh_.setParam(desc->name, user);
    else
      nh_.deleteParam(desc->name);
    forgotten.insert(desc->name);
  }
  return forgotten;
}

void ReconfigureRecord::recordUserSettings(const FluidConfig& config,
                                           const std::set<std::string>& user_names) const {
  nh_.deleteParam(kKey);
  for (const auto& desc : FluidConfig::__getParamDescriptions__())
    if (user_names.count(desc->name)) desc->toServer(user_nh_, config);
}

void ReconfigureRecord::recordWritten(const FluidConfig& config) const {
  config.__toServer__(written_nh_);
}

}  // namespace pbf_ros
