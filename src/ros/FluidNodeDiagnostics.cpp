// /diagnostics of pbf_node: the simulation's health (reportHealth, FluidDiagnostics.cpp) and
// the rate of every published topic (TopicRateDiagnostic), on diagnostic_updater's Updater.
#include <cmath>

#include <boost/thread/locks.hpp>

#include "pbf_ros/ros/FluidNode.h"

namespace pbf_ros {

void FluidNode::startDiagnostics() {
  // Named after the node (its private namespace): in a nodelet manager, this_node is the
  // manager.
  diagnostics_ = std::make_unique<diagnostic_updater::Updater>(nh_, pnh_, pnh_.getNamespace());
  diagnostics_->setHardwareID("pbf_solver");
  diagnostics_->add("simulation", this, &FluidNode::diagnose);
  diagnostics_->add(cloud_rate_);
  diagnostics_->add(stats_rate_);
  diagnostics_->add(image_rate_);
  diagnostics_->add(depth_rate_);
  // The Updater's own update() is paced by ros::Time, which stands still while a paused
  // simulation holds /clock; a wall timer at the Updater's period (~diagnostic_period,
  // default 1 s, re-read on every update) keeps /diagnostics coming either way.
  last_diagnostic_period_ = diagnostics_->getPeriod();
  diagnostics_timer_ = nh_.createWallTimer(
      ros::WallDuration(last_diagnostic_period_),
      [this](const ros::WallTimerEvent&) { publishDiagnostics(); });
}

void FluidNode::publishDiagnostics() {
  double publish_rate = 0.0, stats_rate = 0.0, render_rate = 0.0;
  {
    // The reconfigure server holds this mutex while it changes applied_config_.
    boost::recursive_mutex::scoped_lock lock(reconfigure_mutex_);
    publish_rate = applied_config_.publish_rate;
    stats_rate = applied_config_.stats_rate;
    render_rate = applied_config_.render_rate;
  }
  // The rates are wall-clock rates, FrequencyStatus counts per second of the ROS clock: on
  // this node's own /clock that is a simulated second, which lasts 1/factor wall seconds.
  double ros_seconds_per_wall_second = 1.0;
  if (publish_clock_ && ros::Time::isSimTime()) {
    std::lock_guard<std::mutex> lock(health_mutex_);
    ros_seconds_per_wall_second = health_.running ? health_.achieved_factor : 0.0;
  }
  auto expected = [&](double wall_hz) {
    return ros_seconds_per_wall_second > 0.0 ? wall_hz / ros_seconds_per_wall_second : 0.0;
  };
  cloud_rate_.setExpectedRate(expected(publish_rate));
  stats_rate_.setExpectedRate(expected(stats_rate));
  image_rate_.setExpectedRate(expected(render_rate));
  depth_rate_.setExpectedRate(expected(render_rate));

  diagnostics_->force_update();  // re-reads ~diagnostic_period
  const double period = diagnostics_->getPeriod();
  if (period > 0.0 && std::abs(period - last_diagnostic_period_) > 1e-9) {
    diagnostics_timer_.setPeriod(ros::WallDuration(period));
    last_diagnostic_period_ = period;
  }
}

// Why a surface topic is not flowing now, or "" when it should be.
std::string FluidNode::surfaceIdle(int subscribers) const {
  if (surface_status_.unavailable) return "no surface rendering (no GL context)";
  if (subscribers <= 0) return "no subscriber";
  if (paused_) return "paused (a state is rendered once)";
  return "";
}

void FluidNode::diagnose(diagnostic_updater::DiagnosticStatusWrapper& status) {
  HealthSample sample;
  {
    std::lock_guard<std::mutex> lock(health_mutex_);
    sample = health_;
    health_.nan_recoveries_recent = 0;
    health_.failed_steps_recent = 0;
    health_.steps_recent = 0;
    health_.capped_steps_recent = 0;
  }
  reportHealth(sample, thresholds_, status);
  // The surface renderer's work (its own thread; see SurfaceRenderThread).
  const bool rendering = surface_status_.active.load();
  if (surface_status_.unavailable.load()) {
    status.add("surface rendering", "unavailable: no GL context (see the node's log)");
    status.mergeSummary(diagnostic_msgs::DiagnosticStatus::WARN,
                        "no surface rendering (GL back-end failed)");
  } else {
    status.add("surface rendering", rendering ? "active (subscribed)" : "idle (no subscriber)");
  }
  status.add("surface frames rendered", surface_status_.frames.load());
  status.add("surface frame time [ms]", rendering ? surface_status_.last_frame_ms.load() : 0.0);
}

}  // namespace pbf_ros
