#pragma once
// Health of the simulation for /diagnostics: OK / WARN / ERROR from the real-time factor,
// the density error, steps that stopped at max_iterations and NaN recoveries. A plain
// function of a sample, unit-testable.

#include <cstdint>
#include <diagnostic_updater/DiagnosticStatusWrapper.h>
#include <string>

namespace pbf_ros {

struct HealthThresholds {
  double rtf_warn_ratio = 0.9;     // achieved / requested below this: WARN
  double rtf_error_ratio = 0.25;   // ... below this: ERROR
  double density_error_warn = 0.05;   // average density error above this: WARN
  double density_error_error = 0.2;   // ... above this: ERROR
  // Steps whose solve stopped at max_iterations above density_tolerance, as a fraction of
  // the steps since the previous report, above this: WARN (the accuracy asked for is not
  // reached; a single capped step, e.g. at an impact, is not worth a warning).
  double capped_steps_warn_fraction = 0.1;
};

struct HealthSample {
  std::string scene;
  bool paused = false;
  bool running = false;               // at least one step since start/resume was taken
  double requested_factor = 1.0;      // 0 = as fast as possible
  double achieved_factor = 0.0;
  double sim_time = 0.0;
  std::uint64_t step_count = 0;
  std::uint32_t particle_count = 0;
  double avg_density_error = 0.0;
  double max_density_error = 0.0;
  double max_speed = 0.0;
  int iterations = 0;
  double dt = 0.0;
  std::uint64_t nan_recoveries_total = 0;   // since the last reset
  std::uint32_t nan_recoveries_recent = 0;  // since the previous report
  std::uint32_t failed_steps_recent = 0;    // steps given up since the previous report
  std::uint32_t steps_recent = 0;           // steps taken since the previous report
  std::uint32_t capped_steps_recent = 0;    // ... whose solve stopped at max_iterations
  int max_iterations = 0;                   // the cap, to name it in the report
  std::string last_refused;                 // last refused request, for the user to see
};

void reportHealth(const HealthSample& sample, const HealthThresholds& thresholds,
                  diagnostic_updater::DiagnosticStatusWrapper& status);

}  // namespace pbf_ros
