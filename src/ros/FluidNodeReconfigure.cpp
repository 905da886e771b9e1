// dynamic_reconfigure: check a request, decide per level bit what must be redone, and hand
// the change to the simulation thread (applied between steps). The callback waits for the
// simulation thread, so when the reconfigure call returns the change is in force.

#include "pbf_ros/ros/EchoedText.h"
#include "pbf_ros/ros/FluidNode.h"
#include "pbf_ros/ros/ParamsConversion.h"
#include "pbf_ros/ros/ReconfigureLevels.h"
#include "pbf_ros/ros/RenderCameraParams.h"
#include "pbf_ros/ros/SceneLoading.h"

namespace pbf_ros {

void FluidNode::refuse(const std::string& what) {
  ROS_WARN("pbf_node: %s", what.c_str());
  std::lock_guard<std::mutex> lock(health_mutex_);
  health_.last_refused = what;
}

void FluidNode::onReconfigure(FluidConfig& config, std::uint32_t /*level*/) {
  if (!reconfigure_live_) {  // the server's first call, during start-up: already in force
    applied_config_ = config;
    return;
  }

  // Information, not a warning: a slider dragged to its end, or 0 to switch a term off, is a
  // value at an end too.
  for (const std::string& note : rangeEndNotes(config, applied_config_)) ROS_INFO("pbf_node: %s", note.c_str());
  for (const std::string& note : sanitizeConfig(config, applied_config_)) refuse(note);

  // What the user has set (start-up parameters, earlier requests, this request) stays set
  // across scene changes; everything else follows the scene.
  std::set<std::string> requested = changedParams(config, applied_config_);
  requested.erase("scene");
  // Moving the camera by hand means that camera, not the automatic one.
  if (applyCameraOverride(requested, config)) requested.insert("camera_auto");
  FluidConfig user_config = user_config_;
  overlayParams(config, requested, user_config);
  std::set<std::string> user_names = user_param_names_;
  user_names.insert(requested.begin(), requested.end());

  // The scene: load and check it here, so a bad one is refused before anything changes.
  pbf::Scene scene = applied_scene_;
  bool rebuild = false;
  if (config.scene != applied_config_.scene) {
    try {
      scene = loadScene(config.scene, scenes_dir_);
      rebuild = true;
      // The new scene brings its solver settings; the user's own settings stay on top.
      FluidConfig fresh = config;
      solverParamsToConfig(scene.solver, fresh);
      overlayParams(user_config, user_names, fresh);
      for (const std::string& note : sanitizeConfig(fresh, applied_config_)) refuse(note);
      config = fresh;
    } catch (const std::exception& e) {  // any failure, foreseen or not, is a refusal
      refuse("scene '" + echoed(config.scene) + "' refused (" + echoed(e.what(), 4 * kEchoedChars) +
             "); '" + echoed(applied_config_.scene) + "' keeps running");
      config = applied_config_;  // the server then shows what runs
      return;
    }
  }

  const std::uint32_t level = config.__level__(applied_config_);
  if (level == 0) {
    config = applied_config_;
    return;
  }
  if ((level & ~level::kRender) == 0) {
    // Rendering only: the render thread takes it; the solver and its thread are not involved.
    applied_config_ = config;
    user_config_ = user_config;
    user_param_names_ = user_names;
    notifyRenderSettings();
    return;
  }
  rebuild = rebuild || (level & level::kResolution);

  const pbf::SolverParams params = configToSolverParams(config, scene.solver);
  const std::string invalid = params.validate();
  if (!invalid.empty()) {
    refuse("reconfigure refused: " + invalid + "; previous parameters kept");
    config = applied_config_;
    return;
  }
  if (rebuild) {
    // Refuse resolutions that would ask for more particles than the node allows, counted
    // before anything is allocated.
    pbf::Scene probe = scene;
    probe.solver = params;
    std::string why = probe.validate();
    if (why.empty()) why = probe.checkParticleCount(max_particles_);
    if (!why.empty()) {
      const std::string asked = config.scene != applied_config_.scene
                                    ? "scene '" + echoed(config.scene) + "' refused: "
                                    : std::string("reconfigure refused: ");
      refuse(asked + why + "; '" + echoed(applied_config_.scene) + "' keeps running");
      config = applied_config_;
      return;
    }
  }

  const bool solver_change = (level & level::kAnySolverParam) != 0;
  const double factor = config.real_time_factor;
  const double publish_rate = config.publish_rate, stats_rate = config.stats_rate;
  const bool pacing_change = (level & level::kPacing) != 0;
  const bool publishing_change = (level & level::kPublishing) != 0;
  const std::string error = runOnSimulation([=]() -> std::string {
    if (rebuild) {
      const std::string e = rebuildFluid(scene, params);
      if (!e.empty()) return e;
    } else if (solver_change) {
      try {
        solver_->setParams(params);  // the fluid keeps its state
        scene_.solver = params;
      } catch (const std::exception& e) {
        return e.what();
      }
    }
    if (publishing_change) setRates(publish_rate, stats_rate);
    if (pacing_change) {
      pacer_.setFactor(factor);
      pacer_.restart(pacingNow(), sim_clock_);
      // Above real time the stamps ran ahead of ROS time; back at or below it they would stay
      // ahead for good: they go on from now.
      if (!publish_clock_ && stamp() > ros::Time::now()) anchorStamps();
    }
    return "";
  });
  if (!error.empty()) {
    refuse("reconfigure refused: " + error + "; the running simulation is unchanged");
    config = applied_config_;
    return;
  }
  if (rebuild) {
    ROS_INFO("pbf_node: %s scene '%s' (spacing %.4g m)",
             (level & level::kScene) ? "switched to" : "rebuilt", config.scene.c_str(),
             config.particle_spacing);
  }
  applied_config_ = config;
  applied_scene_ = scene;
  applied_scene_.solver = params;
  user_config_ = user_config;
  user_param_names_ = user_names;
  if (level & (level::kRender | level::kScene)) notifyRenderSettings();
}

}  // namespace pbf_ros
