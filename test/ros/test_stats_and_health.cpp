// StatsConversion and FluidDiagnostics: plain functions of the solver's numbers.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>

#include "pbf_ros/ros/FluidDiagnostics.h"
#include "pbf_ros/ros/StatsConversion.h"

using diagnostic_msgs::DiagnosticStatus;

TEST(StatsConversion, CopiesTheStepAndAddsTheNodeContext) {
  pbf::StepStats s;
  s.dt = 0.004;
  s.iterations = 3;
  s.avg_density_error = 0.01;
  s.max_density_error = 0.05;
  s.max_speed = 2.0;
  s.kinetic_energy = 12.0;
  s.neighbor_lists_reused = true;
  s.times.solve_ms = 1.5;
  s.times.total_ms = 3.0;
  s.skipped_stages.add(pbf::SkippedStages::kVorticity);
  pbf_ros::StatsContext c;
  c.frame_id = "fluid_domain";
  c.sim_time = 1.25;
  c.step_count = 42;
  c.particle_count = 1000;
  c.real_time_factor = 0.8;
  c.cloud_ms = 0.7;
  c.cloud_skipped = false;
  const pbf_ros::SimulationStats m = pbf_ros::toStatsMessage(s, c);
  EXPECT_EQ(m.header.frame_id, "fluid_domain");
  EXPECT_DOUBLE_EQ(m.sim_time, 1.25);
  EXPECT_EQ(m.step_count, 42u);
  EXPECT_EQ(m.particle_count, 1000u);
  EXPECT_EQ(m.iterations, 3u);
  EXPECT_DOUBLE_EQ(m.time_solve_ms, 1.5);
  EXPECT_DOUBLE_EQ(m.time_cloud_ms, 0.7);
  EXPECT_DOUBLE_EQ(m.real_time_factor, 0.8);
  EXPECT_TRUE(m.neighbor_lists_reused);
  EXPECT_EQ(m.skipped_stages, std::vector<std::string>{"vorticity"});
}

TEST(StatsConversion, SourcesAndDrainsBalanceInTheMessage) {
  pbf_ros::StatsContext c;
  c.particle_count = 1040;
  c.initial_particle_count = 1000;
  c.particles_emitted = 90;
  c.particles_drained = 50;
  c.particle_mass = 0.008;
  const pbf_ros::SimulationStats m = pbf_ros::toStatsMessage(pbf::StepStats(), c);
  EXPECT_EQ(m.initial_particle_count, 1000u);
  EXPECT_EQ(m.particles_emitted, 90u);
  EXPECT_EQ(m.particles_drained, 50u);
  EXPECT_EQ(m.particle_count, m.initial_particle_count + m.particles_emitted - m.particles_drained);
  EXPECT_DOUBLE_EQ(m.particle_mass, 0.008);
  EXPECT_DOUBLE_EQ(m.fluid_mass, 1040 * 0.008);
}

TEST(StatsConversion, SkippedCloudIsListedAndCostsNothing) {
  pbf_ros::StatsContext c;
  c.cloud_ms = 5.0;
  c.cloud_skipped = true;
  const pbf_ros::SimulationStats m = pbf_ros::toStatsMessage(pbf::StepStats(), c);
  EXPECT_DOUBLE_EQ(m.time_cloud_ms, 0.0);
  EXPECT_NE(std::find(m.skipped_stages.begin(), m.skipped_stages.end(), "cloud"),
            m.skipped_stages.end());
}

TEST(StatsConversion, SurfaceWorkIsReportedAndSkippedSurfaceCostsNothing) {
  pbf_ros::StatsContext c;
  c.render_ms = 12.5;
  c.render_frames = 7;
  c.render_skipped = false;
  pbf_ros::SimulationStats m = pbf_ros::toStatsMessage(pbf::StepStats(), c);
  EXPECT_DOUBLE_EQ(m.time_render_ms, 12.5);
  EXPECT_EQ(m.surface_frames, 7u);
  EXPECT_EQ(std::find(m.skipped_stages.begin(), m.skipped_stages.end(), "surface"),
            m.skipped_stages.end());
  c.render_skipped = true;
  m = pbf_ros::toStatsMessage(pbf::StepStats(), c);
  EXPECT_DOUBLE_EQ(m.time_render_ms, 0.0);
  EXPECT_EQ(m.surface_frames, 7u);  // the total stays
  EXPECT_NE(std::find(m.skipped_stages.begin(), m.skipped_stages.end(), "surface"),
            m.skipped_stages.end());
}

TEST(StatsConversion, NonFiniteNumbersNeverReachTheMessage) {
  pbf::StepStats s;
  s.max_speed = std::numeric_limits<double>::quiet_NaN();
  s.kinetic_energy = std::numeric_limits<double>::infinity();
  const pbf_ros::SimulationStats m = pbf_ros::toStatsMessage(s, pbf_ros::StatsContext());
  EXPECT_DOUBLE_EQ(m.max_speed, 0.0);
  EXPECT_DOUBLE_EQ(m.kinetic_energy, 0.0);
}

namespace {
unsigned char levelOf(const pbf_ros::HealthSample& s) {
  diagnostic_updater::DiagnosticStatusWrapper status;
  pbf_ros::reportHealth(s, pbf_ros::HealthThresholds(), status);
  return status.level;
}
pbf_ros::HealthSample healthy() {
  pbf_ros::HealthSample s;
  s.running = true;
  s.requested_factor = 1.0;
  s.achieved_factor = 1.0;
  s.avg_density_error = 0.01;
  return s;
}
}  // namespace

TEST(FluidDiagnostics, HealthyIsOk) { EXPECT_EQ(levelOf(healthy()), DiagnosticStatus::OK); }

TEST(FluidDiagnostics, SlowRealTimeFactorWarnsThenErrs) {
  auto s = healthy();
  s.achieved_factor = 0.5;
  EXPECT_EQ(levelOf(s), DiagnosticStatus::WARN);
  s.achieved_factor = 0.1;
  EXPECT_EQ(levelOf(s), DiagnosticStatus::ERROR);
  s.paused = true;  // paused is not slow
  EXPECT_EQ(levelOf(s), DiagnosticStatus::OK);
  s.paused = false;
  s.requested_factor = 0.0;  // as fast as possible: any speed is fine
  EXPECT_EQ(levelOf(s), DiagnosticStatus::OK);
}

TEST(FluidDiagnostics, DensityErrorWarnsThenErrs) {
  auto s = healthy();
  s.avg_density_error = 0.1;
  EXPECT_EQ(levelOf(s), DiagnosticStatus::WARN);
  s.avg_density_error = 0.5;
  EXPECT_EQ(levelOf(s), DiagnosticStatus::ERROR);
}

TEST(FluidDiagnostics, StepsStoppedAtTheIterationCapWarnAboveTheirFraction) {
  auto s = healthy();
  s.steps_recent = 100;
  s.max_iterations = 30;
  s.capped_steps_recent = 10;  // 10 %: at the threshold, not above
  EXPECT_EQ(levelOf(s), DiagnosticStatus::OK);
  s.capped_steps_recent = 11;
  EXPECT_EQ(levelOf(s), DiagnosticStatus::WARN);
  diagnostic_updater::DiagnosticStatusWrapper status;
  pbf_ros::reportHealth(s, pbf_ros::HealthThresholds(), status);
  EXPECT_NE(status.message.find("11 of 100 steps stopped at max_iterations (30)"), std::string::npos)
      << status.message;
  s.steps_recent = 0;  // a report with no step since the previous one
  s.capped_steps_recent = 0;
  EXPECT_EQ(levelOf(s), DiagnosticStatus::OK);
}

TEST(FluidDiagnostics, NanRecoveriesWarnAndFailedStepsErr) {
  auto s = healthy();
  s.nan_recoveries_recent = 2;
  EXPECT_EQ(levelOf(s), DiagnosticStatus::WARN);
  s.failed_steps_recent = 1;
  EXPECT_EQ(levelOf(s), DiagnosticStatus::ERROR);
}
