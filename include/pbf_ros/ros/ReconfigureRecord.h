#pragma once
// Tells the parameters a user set apart from those dynamic_reconfigure left behind.
//
// dynamic_reconfigure writes every value it serves into the node's private namespace. A
// later node on the same master (a relaunch, a respawn, a rosrun) would read all of them as
// set by the user: a scene's own `solver:` values would then never apply again. So the node
// keeps a record beside them, under ~reconfigure_record/:
//   written/<name>  the values it last handed to the reconfigure server (so to the server);
//   user/<name>     the values the user had set when the node started.
// At the next start, a parameter whose value is still what the last run wrote was left
// behind by that run: it goes back to the user's value if the user had set it, otherwise it
// is deleted. Any other value was set by someone else since, and counts as the user's. A
// relaunch then starts like a first launch, even after a crash.

#include <set>
#include <string>

#include <ros/node_handle.h>

#include <pbf_ros/FluidConfig.h>

namespace pbf_ros {

class ReconfigureRecord {
 public:
  static constexpr const char* kKey = "reconfigure_record";  // under the private namespace

  explicit ReconfigureRecord(const ros::NodeHandle& private_nh);

  // Undoes what the previous run wrote (see above). Returns the names it restored or
  // deleted, for the log. Call before reading any Fluid.cfg parameter.
  std::set<std::string> forgetPreviousRun() const;

  // Starts a new record: `config`'s values of `user_names` are what the user set.
  void recordUserSettings(const FluidConfig& config, const std::set<std::string>& user_names) const;

  // Notes `config` as what the reconfigure server is about to write.
  void recordWritten(const FluidConfig& config) const;

 private:
  ros::NodeHandle nh_, written_nh_, user_nh_;
};

}  // namespace pbf_ros
