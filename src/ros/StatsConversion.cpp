#include "pbf_ros/ros/StatsConversion.h"

#include <cmath>

namespace pbf_ros {

namespace {
double finiteOr0(double x) { return std::isfinite(x) ? x : 0.0; }
}  // namespace

SimulationStats toStatsMessage(const pbf::StepStats& stats, const StatsContext& context) {
  SimulationStats msg;
  msg.header.stamp = context.stamp;
  msg.header.frame_id = context.frame_id;
  msg.sim_time = finiteOr0(context.sim_time);
  msg.step_count = context.step_count;
  msg.particle_count = context.particle_count;
  msg.dt = finiteOr0(stats.dt);
  msg.iterations = static_cast<std::uint32_t>(stats.iterations < 0 ? 0 : stats.iterations);
  msg.avg_density_error = finiteOr0(stats.avg_density_error);
  msg.max_density_error = finiteOr0(stats.max_density_error);
  msg.max_speed = finiteOr0(stats.max_speed);
  msg.kinetic_energy = finiteOr0(stats.kinetic_energy);
  msg.real_time_factor = finiteOr0(context.real_time_factor);
  msg.nan_recoveries = context.nan_recoveries;
  msg.neighbor_lists_reused = stats.neighbor_lists_reused;
  msg.time_neighbors_ms = finiteOr0(stats.times.neighbors_ms);
  msg.time_solve_ms = finiteOr0(stats.times.solve_ms);
  msg.time_viscosity_vorticity_ms = finiteOr0(stats.times.viscosity_vorticity_ms);
  msg.time_other_ms = finiteOr0(stats.times.other_ms);
  msg.time_total_ms = finiteOr0(stats.times.total_ms);
  msg.time_cloud_ms = context.cloud_skipped ? 0.0 : finiteOr0(context.cloud_ms);
  msg.time_render_ms = context.render_skipped ? 0.0 : finiteOr0(context.render_ms);
  msg.surface_frames = context.render_frames;
  msg.wrench_tracked = context.wrench_tracked && context.solids_wrench.allFinite();
  if (msg.wrench_tracked) {
    msg.solids_wrench.force.x = context.solids_wrench.force.x();
    msg.solids_wrench.force.y = context.solids_wrench.force.y();
    msg.solids_wrench.force.z = context.solids_wrench.force.z();
    msg.solids_wrench.torque.x = context.solids_wrench.torque.x();
    msg.solids_wrench.torque.y = context.solids_wrench.torque.y();
    msg.solids_wrench.torque.z = context.solids_wrench.torque.z();
  }
  msg.initial_particle_count = context.initial_particle_count;
  msg.particles_emitted = context.particles_emitted;
  msg.particles_drained = context.particles_drained;
  msg.particle_mass = finiteOr0(context.particle_mass);
  msg.fluid_mass = finiteOr0(context.particle_mass * context.particle_count);
  msg.skipped_stages = stats.skipped_stages.names();
  if (context.cloud_skipped) msg.skipped_stages.push_back("cloud");
  if (context.render_skipped) msg.skipped_stages.push_back("surface");
  return msg;
}

}  // namespace pbf_ros
