#include "pbf_ros/ros/TopicRateDiagnostic.h"

#include <diagnostic_msgs/DiagnosticStatus.h>

#include <stdexcept>

namespace pbf_ros {

TopicRateDiagnostic::TopicRateDiagnostic(const std::string& name,
                                         std::function<std::string()> idle)
    : DiagnosticTask(name),
      idle_(std::move(idle)),
      frequency_(diagnostic_updater::FrequencyStatusParam(&min_hz_, &max_hz_, 0.1, 5), name) {}

void TopicRateDiagnostic::setExpectedRate(double max_hz) {
  std::lock_guard<std::mutex> lock(mutex_);
  max_hz_ = max_hz;
  min_hz_ = 0.5 * max_hz;
}

void TopicRateDiagnostic::run(diagnostic_updater::DiagnosticStatusWrapper& status) {
  std::lock_guard<std::mutex> lock(mutex_);
  std::string why = idle_ ? idle_() : std::string();
  if (why.empty() && !(max_hz_ > 0.0)) why = "expected rate not known yet";
  if (!why.empty()) {
    // Forget the silent stretch: the first report after it must not average it in.
    frequency_.clear();
    measuring_ = false;
    status.summary(diagnostic_msgs::DiagnosticStatus::OK, "idle: " + why);
    status.add("Maximum expected frequency (Hz)", max_hz_);
    return;
  }
  // FrequencyStatus measures on the ROS clock. Across a jump of that clock (a /clock that
  // goes back, or a replayed bag's far jump) its window means nothing, and a jump beyond
  // 2^31 s made its ros::Time subtraction throw out of the diagnostics timer, which took
  // the node down: measure again from now instead.
  const double now = ros::Time::now().toSec();
  const bool jumped = measuring_ && !(now >= last_report_ && now - last_report_ < kLongestWindow);
  last_report_ = now;
  if (!measuring_ || jumped) {
    // The topic just started flowing: measure from now on, judge from the next report.
    frequency_.clear();
    measuring_ = true;
    status.summary(diagnostic_msgs::DiagnosticStatus::OK,
                   jumped ? "the ROS clock jumped; measuring the rate again" : "started; measuring the rate");
    status.add("Maximum expected frequency (Hz)", max_hz_);
    return;
  }
  try {
    frequency_.run(status);
  } catch (const std::runtime_error&) {  // ros::Time out of range, should the clock still jump
    frequency_.clear();
    status.summary(diagnostic_msgs::DiagnosticStatus::OK, "the ROS clock jumped; measuring the rate again");
    status.add("Maximum expected frequency (Hz)", max_hz_);
  }
}

}  // namespace pbf_ros
