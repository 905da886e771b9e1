#include "pbf_ros/ros/TopicRateDiagnostic.h"

#include <diagnostic_msgs/DiagnosticStatus.h>

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
  if (!measuring_) {
    // The topic just started flowing: measure from now on, judge from the next report.
    frequency_.clear();
    measuring_ = true;
    status.summary(diagnostic_msgs::DiagnosticStatus::OK, "started; measuring the rate");
    status.add("Maximum expected frequency (Hz)", max_hz_);
    return;
  }
  frequency_.run(status);
}

}  // namespace pbf_ros
