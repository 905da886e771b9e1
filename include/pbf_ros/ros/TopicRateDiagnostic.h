#pragma once
// One published topic's rate on /diagnostics: diagnostic_updater's FrequencyStatus against
// the rate the node is configured to publish at, reported only while the topic is meant to
// flow. pbf_node publishes lazily (nothing without a subscriber) and each state once
// (nothing new while paused); a bare FrequencyStatus would call that healthy silence
// "No events recorded" (ERROR). While idle, the status is OK and says why.

#include <functional>
#include <mutex>
#include <string>

#include <diagnostic_updater/DiagnosticStatusWrapper.h>
#include <diagnostic_updater/update_functions.h>

namespace pbf_ros {

class TopicRateDiagnostic : public diagnostic_updater::DiagnosticTask {
 public:
  // idle(): "" while the topic is meant to flow, otherwise why it does not (any thread).
  TopicRateDiagnostic(const std::string& name, std::function<std::string()> idle);

  // The rate the topic is meant to have, in messages per second of the ROS clock
  // FrequencyStatus measures with: at least half of max_hz, at most max_hz (each with
  // FrequencyStatus's 10 % tolerance). max_hz <= 0: not known now (reported as idle).
  void setExpectedRate(double max_hz);
  void tick() { frequency_.tick(); }  // a message was published (any thread)

  void run(diagnostic_updater::DiagnosticStatusWrapper& status) override;

 private:
  std::mutex mutex_;  // guards what follows; FrequencyStatus reads min_hz_/max_hz_ in run()
  double min_hz_ = 0.0, max_hz_ = 0.0;
  bool measuring_ = false;  // the previous report measured (the window is valid)
  // The ROS time of the previous report [s]; reports further apart than this, or going back,
  // mean the clock jumped (the updater reports about once a wall second).
  double last_report_ = 0.0;
  static constexpr double kLongestWindow = 3600.0;
  std::function<std::string()> idle_;
  diagnostic_updater::FrequencyStatus frequency_;
};

}  // namespace pbf_ros
