// Start-up of pbf_node: settings, scene, solver, ROS interface, then the simulation thread.
#include "pbf_ros/ros/FluidNode.h"

#include <omp.h>
#include <ros/master.h>
#include <rosgraph_msgs/Clock.h>
#include <stdexcept>
#include <visualization_msgs/MarkerArray.h>

#include <pbf_ros/SimulationStats.h>

#include "pbf_ros/ros/NodeParams.h"
#include "pbf_ros/ros/ParamsConversion.h"
#include "pbf_ros/ros/RenderCameraParams.h"
#include "pbf_ros/ros/SceneLoading.h"

namespace pbf_ros {

namespace {

// Whether another node publishes /clock now (the master's list of published topics).
bool clockHasPublisher() {
  ros::master::V_TopicInfo topics;
  if (!ros::master::getTopics(topics)) return false;
  for (const ros::master::TopicInfo& t : topics)
    if (t.name == "/clock") return true;
  return false;
}

// Whether a parameter server value can be read as a Fluid.cfg parameter of `type`.
bool hasType(const XmlRpc::XmlRpcValue& value, const std::string& type) {
  switch (value.getType()) {
    case XmlRpc::XmlRpcValue::TypeDouble: return type == "double";
    case XmlRpc::XmlRpcValue::TypeInt: return type == "int" || type == "double";
    case XmlRpc::XmlRpcValue::TypeBoolean: return type == "bool";
    case XmlRpc::XmlRpcValue::TypeString: return type == "str";
    default: return false;
  }
}

}  // namespace

FluidNode::FluidNode(ros::NodeHandle nh, ros::NodeHandle private_nh)
    : nh_(nh),
      pnh_(private_nh),
      record_(private_nh),
      cloud_rate_("topic " + private_nh.resolveName("particles"),
                  [this] {
                    if (particles_pub_.getNumSubscribers() == 0) return "no subscriber";
                    return paused_ ? "paused (a state is published once)" : "";
                  }),
      stats_rate_("topic " + private_nh.resolveName("stats"),
                  [this] { return stats_pub_.getNumSubscribers() == 0 ? "no subscriber" : ""; }),
      image_rate_("topic " + private_nh.resolveName("rgb/image_rect_color"),
                  [this] { return surfaceIdle(surface_status_.image_subscribers); }),
      depth_rate_("topic " + private_nh.resolveName("depth_registered/image_rect"),
                  [this] { return surfaceIdle(surface_status_.depth_subscribers); }) {
  // Before anything reads a parameter: values the previous run's reconfigure server left
  // on the master are not the user's (a relaunch starts like a first launch).
  const std::set<std::string> forgotten = record_.forgetPreviousRun();
  if (!forgotten.empty()) {
    std::string names;
    for (const std::string& n : forgotten) names += (names.empty() ? "" : ", ") + n;
    ROS_INFO("pbf_node: ignoring the values a previous run left in %s: %s",
             pnh_.getNamespace().c_str(), names.c_str());
  }
  pnh_.getParam(pnh_.getNamespace(), launch_params_);
  readNodeSettings();

  // A bad scene at start-up is fatal: the caller reports it and the node exits non-zero.
  std::string scene_name;
  pnh_.param<std::string>("scene", scene_name, FluidConfig::__getDefault__().scene);
  pbf::Scene scene;
  try {
    scene = loadScene(scene_name, scenes_dir_);
  } catch (const std::exception& e) {  // SceneError names the file and the key
    throw std::runtime_error(std::string("cannot load scene: ") + e.what());
  }

  FluidConfig config = startupConfig(scene);
  config.scene = scene_name;
  const pbf::SolverParams params = configToSolverParams(config, scene.solver);
  const std::string invalid = params.validate();
  if (!invalid.empty()) throw std::runtime_error("unusable solver parameters: " + invalid);

  advertise();
  // Built on this thread (the node's main thread, or the nodelet manager's) with a single
  // OpenMP thread. A thread that runs a parallel region keeps an OpenMP pool of its own, and
  // libgomp counts that pool's idle worker as one of its threads: with more threads than
  // cores it cuts the spin before sleeping at a barrier (GOMP_SPINCOUNT, fluid.launch) to
  // 1000 iterations, and the simulation thread's steps lost the 16 % that spin saves. The
  // set-up's loops are short. (Later rebuilds run on the simulation thread.)
  const int openmp_threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const std::string error = rebuildFluid(scene, params);
  omp_set_num_threads(openmp_threads);
  if (!error.empty()) throw std::runtime_error("cannot build the fluid: " + error);
  applied_scene_ = scene_without_robot_;
  pacer_.setFactor(config.real_time_factor);
  setRates(config.publish_rate, config.stats_rate);
  startReconfigure(config);

  ROS_INFO("pbf_node: scene '%s' (%s), %zu particles, spacing %.4g m, real-time factor %g%s",
           scene_.name.c_str(), scene_.source.c_str(), solver_->size(),
           params.particle_spacing, config.real_time_factor, paused_ ? ", paused" : "");

  running_ = true;
  pacer_.restart(pacingNow(), sim_clock_);
  anchorStamps();
  sim_thread_ = std::thread(&FluidNode::runSimulation, this);
  reconfigure_live_ = true;
}

FluidNode::~FluidNode() { stopSimulation(); }

void FluidNode::stopSimulation() {
  running_ = false;
  tasks_.wake();
  if (sim_thread_.joinable()) sim_thread_.join();
}

void FluidNode::readNodeSettings() {
  pnh_.param<std::string>("scenes_dir", scenes_dir_, defaultScenesDir());
  std::string warning;
  auto warn = [&warning] {
    if (!warning.empty()) ROS_WARN("pbf_node: %s", warning.c_str());
  };
  std::string frame;
  pnh_.param<std::string>("world_frame", frame, world_frame_);
  world_frame_ = usableFrameId("world_frame", frame, world_frame_, warning);
  warn();
  pnh_.param<std::string>("frame_id", frame, domain_frame_);
  domain_frame_ = usableFrameId("frame_id", frame, domain_frame_, warning);
  warn();
  publish_clock_ = readBool(pnh_, "publish_clock", publish_clock_);
  paused_ = readBool(pnh_, "start_paused", false);
  bool use_sim_time = false;
  ros::param::get("/use_sim_time", use_sim_time);
  if (use_sim_time != publish_clock_) {
    if (use_sim_time && clockHasPublisher()) {  // a simulator's or a bag's: follow it
      ROS_INFO("pbf_node: on /use_sim_time, following the /clock another node publishes");
    } else {
      ROS_WARN("pbf_node: ~publish_clock is %s but /use_sim_time is %s: %s",
               publish_clock_ ? "true" : "false", use_sim_time ? "true" : "false",
               publish_clock_ ? "other nodes ignore the simulated /clock this node publishes"
                              : "every node waits for a /clock, which nobody publishes yet (a "
                                "leftover of an earlier launch? fluid.launch sets it every time)");
    }
  }
  int max_particles = static_cast<int>(max_particles_);
  max_particles = readInteger(pnh_, "max_particles", max_particles);
  if (max_particles < 1) {
    ROS_WARN("pbf_node: ~max_particles %d is not positive; using 1000000", max_particles);
    max_particles = 1000000;
  }
  max_particles_ = static_cast<std::size_t>(max_particles);
  robot_source_ = readRobotSource(pnh_);
  wrench_rate_ = readNumber(pnh_, "wrench_rate", wrench_rate_);
  if (!(wrench_rate_ > 0.0 && wrench_rate_ <= 1000.0)) {
    ROS_WARN("pbf_node: ~wrench_rate %g is not in (0, 1000] Hz; using 30", wrench_rate_);
    wrench_rate_ = 30.0;
  }
  track_wrenches_ = readBool(pnh_, "track_wrenches", track_wrenches_);
  // Each within a range that means something; outside it, the default, with a warning.
  auto number = [&](const std::string& name, double fallback, double lo, double hi) {
    const double value = withinRange(name, readNumber(pnh_, name, fallback), lo, hi, fallback, warning);
    warn();
    return value;
  };
  pacer_ = RealTimePacer(number("max_lag", 0.1, 1e-3, 3600.0));  // wall s of debt dropped
  pacer_.setLagByDuration(followsRosClock());  // a coarse clock's tick is no lag
  HealthThresholds& t = thresholds_;
  t.rtf_warn_ratio = number("diagnostics/rtf_warn_ratio", t.rtf_warn_ratio, 0.0, 1.0);
  t.rtf_error_ratio = number("diagnostics/rtf_error_ratio", t.rtf_error_ratio, 0.0, 1.0);
  // Average density errors (0.05 = 5 %): 0 or less would warn at every step.
  t.density_error_warn = number("diagnostics/density_error_warn", t.density_error_warn, 1e-6, 10.0);
  t.density_error_error = number("diagnostics/density_error_error", t.density_error_error, 1e-6, 10.0);
  double& capped = t.capped_steps_warn_fraction;
  capped = readNumber(pnh_, "diagnostics/capped_steps_warn_fraction", capped);
  if (!(capped >= 0.0 && capped <= 1.0)) {
    const double fallback = HealthThresholds().capped_steps_warn_fraction;
    ROS_WARN("pbf_node: ~diagnostics/capped_steps_warn_fraction %g is not in [0, 1]; using %g",
             capped, fallback);
    capped = fallback;
  }
}

// Precedence: Fluid.cfg defaults < the scene's `solver:` map < parameters the user set in
// the private namespace (YAML, launch file) < later reconfigure requests.
FluidConfig FluidNode::startupConfig(const pbf::Scene& scene) {
  user_config_ = FluidConfig::__getDefault__();
  user_config_.__fromServer__(pnh_);
  for (const auto& desc : FluidConfig::__getParamDescriptions__()) {
    XmlRpc::XmlRpcValue value;
    if (desc->name == "scene" || !pnh_.getParam(desc->name, value)) continue;
    if (!hasType(value, desc->type)) {
      // getParam would silently keep the default: say so instead.
      ROS_ERROR("pbf_node: parameter ~%s: expected type %s (see config/Fluid.cfg), got %s; "
                "ignored", desc->name.c_str(), desc->type.c_str(), describeParam(value).c_str());
      continue;
    }
    user_param_names_.insert(desc->name);
  }
  // A camera position given at start-up means that camera, not the automatic one.
  if (applyCameraOverride(user_param_names_, user_config_)) user_param_names_.insert("camera_auto");
  std::set<std::string> recorded = user_param_names_;
  if (pnh_.hasParam("scene")) recorded.insert("scene");
  record_.recordUserSettings(user_config_, recorded);

  // What a refused value falls back to: Fluid.cfg's default, or the scene's for a solver
  // parameter. Not the user's configuration: a NaN there would be "kept" (a NaN stats_rate
  // silenced ~stats, a NaN camera position went out on tf).
  FluidConfig from_scene = FluidConfig::__getDefault__();
  solverParamsToConfig(scene.solver, from_scene);
  FluidConfig config = from_scene;
  overlayParams(user_config_, user_param_names_, config);
  for (const std::string& note : sanitizeConfig(config, from_scene))
    ROS_WARN("pbf_node: parameter %s", note.c_str());
  return config;
}

void FluidNode::advertise() {
  // A newcomer gets the current state even when it does not change (paused).
  particles_pub_ = pnh_.advertise<sensor_msgs::PointCloud2>(
      "particles", 2, [this](const ros::SingleSubscriberPublisher&) {
        cloud_wanted_ = true;
        tasks_.wake();
      });
  stats_pub_ = pnh_.advertise<SimulationStats>("stats", 10);
  markers_pub_ = pnh_.advertise<visualization_msgs::MarkerArray>("markers", 1, /*latch=*/true);
  if (publish_clock_) clock_pub_ = nh_.advertise<rosgraph_msgs::Clock>("/clock", 10);
  if (followsRosClock()) {
    clock_sub_ = nh_.subscribe<rosgraph_msgs::Clock>(
        "/clock", 1, [this](const rosgraph_msgs::Clock::ConstPtr&) { tasks_.wake(); });
  }
  wrench_pubs_ = std::make_unique<SolidWrenchPublishers>(pnh_, wrench_rate_, track_wrenches_);

  reset_srv_ = pnh_.advertiseService("reset", &FluidNode::onResetService, this);
  pause_srv_ = pnh_.advertiseService("pause", &FluidNode::onPauseService, this);
  step_srv_ = pnh_.advertiseService("step", &FluidNode::onStepService, this);
  emit_srv_ = pnh_.advertiseService("emit", &FluidNode::onEmitService, this);
  // Runs its frame lookups on the simulation thread (in apply()), which owns attachments_.
  mover_ = std::make_unique<ObstacleMover>(pnh_, domain_frame_,
                                           [this](const std::string& frame, Eigen::Isometry3f& pose) {
                                             if (!attachments_)
                                               attachments_ = std::make_unique<TfAttachments>(domain_frame_);
                                             return attachments_->currentPose(frame, pose);
                                           });

  startDiagnostics();
  master_timer_ = nh_.createWallTimer(ros::WallDuration(1.0),
                                      [this](const ros::WallTimerEvent&) { watchMaster(); });
}

// A master that comes back after a restart has forgotten every topic, service and parameter
// of this node; roscpp does not register again. Rather than run on invisible, the node says
// so and stops (pbf_node exits non-zero so that roslaunch's respawn can start it afresh).
void FluidNode::watchMaster() {
  if (master_lost_) return;
  if (!ros::master::check()) {
    if (!master_down_) ROS_WARN("pbf_node: the ROS master is unreachable; waiting for it");
    master_down_ = true;
    return;
  }
  if (!master_down_) return;
  master_down_ = false;
  XmlRpc::XmlRpcValue request, response, payload;
  request[0] = ros::this_node::getName();
  request[1] = ros::this_node::getName();
  const bool known = ros::master::execute("lookupNode", request, response, payload, false);
  if (known) {
    ROS_INFO("pbf_node: the ROS master is back and still knows this node");
    return;
  }
  master_lost_ = true;
  // roslaunch sets a node's parameters once, on the master it started with: without them a
  // respawned node would run the default scene.
  const bool restored = launch_params_.getType() == XmlRpc::XmlRpcValue::TypeStruct &&
                        restoreLaunchParams();
  ROS_FATAL("pbf_node: the ROS master restarted and no longer knows this node (no topics, "
            "services or parameters); shutting down so that it can be started again%s",
            restored ? " (its launch parameters are back on the master, for a respawn)" : "");
  if (on_master_lost_) on_master_lost_();
}

bool FluidNode::restoreLaunchParams() {
  bool all = true;
  for (const auto& [name, value] : launch_params_) {
    if (name == ReconfigureRecord::kKey) continue;  // the last run's books, not a setting
    // As ros::param::set does, but told whether the master took it.
    XmlRpc::XmlRpcValue request, response, payload;
    request[0] = ros::this_node::getName();
    request[1] = pnh_.getNamespace() + "/" + name;
    request[2] = value;
    all = ros::master::execute("setParam", request, response, payload, false) && all;
  }
  return all;
}

void FluidNode::startReconfigure(const FluidConfig& initial) {
  // The server writes every value to the parameter server: note them first (see
  // ReconfigureRecord). Its constructor writes what it reads, then updateConfig `initial`.
  record_.recordWritten(initial);
  reconfigure_ = std::make_unique<ReconfigureServer>(reconfigure_mutex_, pnh_);
  reconfigure_->updateConfig(initial);  // the scene and YAML values seed the server
  reconfigure_->setCallback([this](FluidConfig& config, std::uint32_t level) {
    onReconfigure(config, level);
    record_.recordWritten(config);  // what the server writes next
  });
}

void FluidNode::setRenderSettingsListener(RenderSettingsListener listener) {
  // The reconfigure server holds this mutex while it calls onReconfigure.
  boost::recursive_mutex::scoped_lock lock(reconfigure_mutex_);
  render_listener_ = std::move(listener);
  notifyRenderSettings();
}

void FluidNode::notifyRenderSettings() {
  if (render_listener_) render_listener_(applied_config_, applied_scene_);
}

void FluidNode::sendStaticTransform(const geometry_msgs::TransformStamped& transform) {
  std::lock_guard<std::mutex> lock(tf_static_mutex_);
  tf_static_.sendTransform(transform);
}

}  // namespace pbf_ros
