// ~reset, ~pause, ~step. Each runs on the simulation thread between steps; the service
// answers once it is done. A request that cannot be served answers success=false with the
// reason, and the simulation carries on untouched.
#include <chrono>
#include <sstream>

#include "pbf_ros/ros/FluidNode.h"

namespace pbf_ros {

std::string FluidNode::runOnSimulation(std::function<std::string()> task) {
  std::future<std::string> done = tasks_.post<std::string>(std::move(task));
  // Waits at most for one step, unless the node is shutting down.
  while (done.wait_for(std::chrono::milliseconds(100)) != std::future_status::ready) {
    if (!running_ || !ros::ok()) return "the node is shutting down";
  }
  try {
    return done.get();
  } catch (const std::exception& e) {
    return e.what();
  }
}

bool FluidNode::onResetService(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
  // Shared, not a reference: after a shutdown timeout the task may still run.
  auto message = std::make_shared<std::string>();
  const std::string error = runOnSimulation([this, message]() -> std::string {
    // Copy: rebuildFluid replaces it. The robot's solids are added afresh (a new URDF).
    const pbf::Scene scene = scene_without_robot_;
    const std::string e = rebuildFluid(scene, solver_->params());
    if (e.empty()) {
      *message = "scene '" + scene_.name + "' reset to its initial state (" +
                std::to_string(solver_->size()) + " particles)" + (paused_ ? ", paused" : "");
    }
    return e;
  });
  res.success = error.empty();
  res.message = error.empty() ? *message : "reset failed: " + error + "; the fluid keeps running";
  if (!res.success) refuse(res.message);
  return true;
}

bool FluidNode::onPauseService(std_srvs::SetBool::Request& req,
                               std_srvs::SetBool::Response& res) {
  const bool pause = req.data;
  auto message = std::make_shared<std::string>();
  const std::string error = runOnSimulation([this, pause, message]() -> std::string {
    const bool was_paused = paused_;
    paused_ = pause;
    if (!pause && was_paused) {
      pacer_.restart(pacingNow(), sim_clock_);  // no debt from the pause
      anchorStamps();                         // stamps go on from now
      stepped_since_resume_ = false;
    }
    std::ostringstream m;
    m << (pause ? (was_paused ? "already paused" : "paused")
                : (was_paused ? "resumed" : "already running"))
      << " at sim time " << solver_->time() << " s (step " << solver_->stepCount() << ")";
    *message = m.str();
    updateHealth();
    return "";
  });
  res.success = error.empty();
  res.message = error.empty() ? *message : error;
  return true;
}

bool FluidNode::onStepService(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
  // Shared, not a reference: after a shutdown timeout the task may still run.
  auto message = std::make_shared<std::string>();
  const std::string error = runOnSimulation([this, message]() -> std::string {
    if (!paused_) return "~step works only while paused; call ~pause with data: true first";
    stepOnce();
    publishDue(wallNow(), /*force=*/true);  // show the user what the step did
    std::ostringstream m;
    m << "stepped to sim time " << solver_->time() << " s (step " << solver_->stepCount()
      << ", dt " << last_stats_.dt << " s" << (last_stats_.failed ? ", step failed" : "")
      << ")";
    *message = m.str();
    return "";
  });
  res.success = error.empty();
  res.message = error.empty() ? *message : error;
  return true;
}

}  // namespace pbf_ros
