#include "pbf_ros/ros/FluidDiagnostics.h"

#include <diagnostic_msgs/DiagnosticStatus.h>
#include <sstream>

namespace pbf_ros {

namespace {
using diagnostic_msgs::DiagnosticStatus;

// Keeps the worst level and joins the reasons.
struct Verdict {
  unsigned char level = DiagnosticStatus::OK;
  std::ostringstream reasons;
  void add(unsigned char l, const std::string& why) {
    if (l > level) level = l;
    if (reasons.tellp() > 0) reasons << "; ";
    reasons << why;
  }
};
}  // namespace

void reportHealth(const HealthSample& s, const HealthThresholds& t,
                  diagnostic_updater::DiagnosticStatusWrapper& status) {
  Verdict verdict;
  std::ostringstream text;

  if (s.paused) {
    verdict.add(DiagnosticStatus::OK, "paused");
  } else if (s.requested_factor > 0.0 && s.running) {
    const double ratio = s.achieved_factor / s.requested_factor;
    text.str("");
    text.precision(3);
    text << "real-time factor " << s.achieved_factor << " of " << s.requested_factor
         << " requested";
    if (ratio < t.rtf_error_ratio)
      verdict.add(DiagnosticStatus::ERROR, text.str());
    else if (ratio < t.rtf_warn_ratio)
      verdict.add(DiagnosticStatus::WARN, text.str());
  }

  text.str("");
  text.precision(3);
  text << "average density error " << s.avg_density_error;
  if (s.avg_density_error > t.density_error_error)
    verdict.add(DiagnosticStatus::ERROR, text.str());
  else if (s.avg_density_error > t.density_error_warn)
    verdict.add(DiagnosticStatus::WARN, text.str());

  if (s.capped_steps_recent > 0 &&
      s.capped_steps_recent > t.capped_steps_warn_fraction * s.steps_recent) {
    text.str("");
    text << s.capped_steps_recent << " of " << s.steps_recent << " steps stopped at max_iterations ("
         << s.max_iterations << ") above density_tolerance";
    verdict.add(DiagnosticStatus::WARN, text.str());
  }

  if (s.failed_steps_recent > 0)
    verdict.add(DiagnosticStatus::ERROR,
                std::to_string(s.failed_steps_recent) + " steps given up (non-finite values)");
  else if (s.nan_recoveries_recent > 0)
    verdict.add(DiagnosticStatus::WARN,
                std::to_string(s.nan_recoveries_recent) + " NaN recoveries");

  std::string summary = verdict.reasons.str();
  if (verdict.level == DiagnosticStatus::OK && !s.paused) summary = "running";
  status.summary(verdict.level, summary);

  status.add("scene", s.scene);
  status.add("paused", s.paused);
  status.add("requested real-time factor", s.requested_factor);
  status.add("achieved real-time factor", s.achieved_factor);
  status.add("sim time [s]", s.sim_time);
  status.add("steps", s.step_count);
  status.add("particles", s.particle_count);
  status.add("dt [s]", s.dt);
  status.add("iterations", s.iterations);
  status.add("steps at max_iterations since previous report", s.capped_steps_recent);
  status.add("average density error", s.avg_density_error);
  status.add("max density error", s.max_density_error);
  status.add("max speed [m/s]", s.max_speed);
  status.add("NaN recoveries since reset", s.nan_recoveries_total);
  if (!s.last_refused.empty()) status.add("last refused request", s.last_refused);
}

}  // namespace pbf_ros
