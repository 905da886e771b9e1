#pragma once
// pbf::StepStats plus what the node knows (time, pacing, cloud and surface work) ->
// SimulationStats.

#include <cstdint>
#include <ros/time.h>
#include <string>

#include <pbf_ros/SimulationStats.h>

#include "pbf_ros/core/SolidWrench.h"
#include "pbf_ros/core/StepStats.h"

namespace pbf_ros {

// What the node adds to the solver's statistics of a step.
struct StatsContext {
  ros::Time stamp;
  std::string frame_id;
  double sim_time = 0.0;            // since the last reset [s]
  std::uint64_t step_count = 0;     // since the last reset
  std::uint32_t particle_count = 0;
  double real_time_factor = 0.0;    // achieved
  std::uint32_t nan_recoveries = 0; // since the last reset
  double cloud_ms = 0.0;            // last ~particles fill
  bool cloud_skipped = false;       // last ~particles opportunity had no subscriber
  bool render_skipped = false;      // no image subscriber (or no GL): nothing rendered
  double render_ms = 0.0;           // last surface frame
  std::uint64_t render_frames = 0;  // surface frames since the node started
  bool wrench_tracked = false;      // solids_wrench was measured (someone wants wrenches)
  pbf::Wrench solids_wrench;        // fluid on all solids, fluid_domain, about its origin
  std::uint32_t initial_particle_count = 0;  // at the last reset
  std::uint64_t particles_emitted = 0;       // since the last reset (emitters, ~emit)
  std::uint64_t particles_drained = 0;       // since the last reset
  double particle_mass = 0.0;                // [kg]
};

// Non-finite numbers become 0 (NaN never reaches a publisher; nan_recoveries tells).
SimulationStats toStatsMessage(const pbf::StepStats& stats, const StatsContext& context);

}  // namespace pbf_ros
