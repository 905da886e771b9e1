#pragma once
// pbf_node: runs a PbfSolver in its own thread and publishes it to ROS.
//
// Threads (ARCHITECTURE.md section 4):
//  - the simulation thread owns the solver, the scene and the pacing. It steps at the
//    requested real-time factor, publishes what is due and runs queued changes between steps;
//  - ROS callbacks (reconfigure, services, diagnostics) run on an AsyncSpinner. They never
//    touch the solver: they post tasks to the simulation thread and wait for the answer;
//  - the surface render thread (SurfaceRenderThread, started beside it by FluidDriver)
//    takes particle snapshots from snapshots() (never blocks), reports into surfaceStatus()
//    (shown in ~stats) and imageRate()/depthRate() (/diagnostics), gets its parameters
//    through setRenderSettingsListener() and sends its camera pose through
//    sendStaticTransform().
//
// Messages go out as shared_ptr<const>: subscribers in the same process (nodelets in one
// manager) receive the published object itself, no copy and no serialisation.

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <diagnostic_updater/diagnostic_updater.h>
#include <dynamic_reconfigure/server.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_srvs/SetBool.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_broadcaster.h>

#include <pbf_ros/Emit.h>
#include <pbf_ros/FluidConfig.h>

#include "pbf_ros/core/FloatingBodies.h"
#include "pbf_ros/core/FluidSources.h"
#include "pbf_ros/core/PbfSolver.h"
#include "pbf_ros/core/Scene.h"
#include "pbf_ros/ros/FluidDiagnostics.h"
#include "pbf_ros/ros/ObstacleMover.h"
#include "pbf_ros/ros/RealTimePacer.h"
#include "pbf_ros/ros/ReconfigureRecord.h"
#include "pbf_ros/ros/RobotSource.h"
#include "pbf_ros/ros/RosClockJumps.h"
#include "pbf_ros/ros/SimulationTasks.h"
#include "pbf_ros/ros/SnapshotBuffer.h"
#include "pbf_ros/ros/SolidWrenchPublishers.h"
#include "pbf_ros/ros/SurfaceRenderStatus.h"
#include "pbf_ros/ros/TfAttachments.h"
#include "pbf_ros/ros/TfStampGate.h"
#include "pbf_ros/ros/TopicRateDiagnostic.h"

namespace pbf_ros {

class FluidNode {
 public:
  // Loads the scene and parameters, advertises everything and starts the simulation thread.
  // Throws std::runtime_error naming what is wrong (bad scene, bad parameter) when the node
  // cannot start.
  FluidNode(ros::NodeHandle nh, ros::NodeHandle private_nh);
  ~FluidNode();  // stops and joins the simulation thread
  // Stops and joins the simulation thread now (idempotent; the destructor calls it): what
  // goes away with the node first, such as the idle-priority render thread, then gets the
  // CPU the solver held. Services and reconfigure answer with an error after it.
  void stopSimulation();
  FluidNode(const FluidNode&) = delete;
  FluidNode& operator=(const FluidNode&) = delete;

  // Particle state for a render thread (see SnapshotBuffer).
  SnapshotBuffer& snapshots() { return snapshots_; }
  // Written by the render thread, reported in ~stats.
  SurfaceRenderStatus& surfaceStatus() { return surface_status_; }

  // Called with the parameters in force and the scene (whose container frames the automatic
  // camera): once right away, then after every reconfigure that changes a render parameter
  // (level bit kRender) or the scene. Runs on the caller's / the spinner's thread; a render-
  // only change never involves the simulation thread. Pass nullptr to stop the calls (do
  // that before whatever the listener refers to goes away).
  using RenderSettingsListener = std::function<void(const FluidConfig&, const pbf::Scene&)>;
  void setRenderSettingsListener(RenderSettingsListener listener);

  // Adds or replaces a transform on the node's one latched /tf_static publisher (any thread).
  void sendStaticTransform(const geometry_msgs::TransformStamped& transform);

  // Called (on the spinner thread) when the master restarted and forgot this node; see
  // watchMaster(). pbf_node shuts down and exits non-zero.
  void setMasterLostHandler(std::function<void()> handler) { on_master_lost_ = std::move(handler); }
  bool masterLost() const { return master_lost_; }

  // Rates of the surface topics on /diagnostics; the render thread ticks them per message.
  TopicRateDiagnostic& imageRate() { return image_rate_; }
  TopicRateDiagnostic& depthRate() { return depth_rate_; }

 private:
  using ReconfigureServer = dynamic_reconfigure::Server<FluidConfig>;

  // --- start-up (FluidNode.cpp) ---
  void readNodeSettings();
  FluidConfig startupConfig(const pbf::Scene& scene);
  void advertise();
  void startReconfigure(const FluidConfig& initial);
  void watchMaster();  // wall timer, spinner thread

  // --- reconfigure (FluidNodeReconfigure.cpp); spinner thread ---
  void onReconfigure(FluidConfig& config, std::uint32_t level);
  void refuse(const std::string& what);
  void notifyRenderSettings();  // calls the listener with applied_config_ / applied_scene_

  // --- services (FluidNodeServices.cpp); spinner thread ---
  bool onResetService(std_srvs::Trigger::Request& req, std_srvs::Trigger::Response& res);
  bool onPauseService(std_srvs::SetBool::Request& req, std_srvs::SetBool::Response& res);
  bool onStepService(std_srvs::Trigger::Request& req, std_srvs::Trigger::Response& res);
  // ~emit (FluidNodeSources.cpp): a block or sphere of fluid added between steps.
  bool onEmitService(Emit::Request& req, Emit::Response& res);
  // Runs `task` on the simulation thread and waits; "" = success, else the error.
  std::string runOnSimulation(std::function<std::string()> task);

  // --- simulation thread (SimulationLoop.cpp) ---
  void runSimulation();
  void stepOnce();
  void publishDue(double wall, bool force);
  void publishCloud(bool force);
  void publishStats();
  void publishClock();
  // Replaces the fluid by the scene's initial state with `params`. "" or the error (the
  // running fluid is untouched then).
  std::string rebuildFluid(const pbf::Scene& scene, const pbf::SolverParams& params);
  void announceScene();  // markers + static tf
  void seedAtCurrentPoses(const pbf::Scene& scene, pbf::PbfSolver& solver);
  // --- robot links as solids (FluidNodeRobot.cpp); simulation thread ---
  // Reads the URDF now and appends the links' solids (at their tf poses) to scene.obstacles.
  std::vector<RobotLinkSolids> addRobotSolids(pbf::Scene& scene);
  void publishFloatingPoses();  // tf of the scene's floating bodies
  // --- sources and drains (FluidNodeSources.cpp); simulation thread ---
  void applySources(double dt);  // after a step: drains, then emitters (at their tf poses)
  void anchorStamps();   // stamps continue from the ROS time now (start, resume, rebuild)
  void followClockJumps();  // ... and after ROS time jumps (RosClockJumps.h)
  // On another node's /clock: stamps that reach `clock_now` when the simulation reaches the
  // pacer's target, so they never lead the clock while it catches up.
  void anchorStampsAtPacerTarget(double clock_now);
  void setRates(double publish_rate, double stats_rate);
  void updateHealth();
  ros::Time stamp() const;
  double wallNow() const;
  // Another node's /clock paces the fluid (/use_sim_time without ~publish_clock): a
  // simulator paused or slowed holds the fluid with it, as it holds every node's timers.
  bool followsRosClock() const;
  // The clock the pacer runs on [s]: ROS time when following /clock, else the wall clock.
  double pacingNow() const;

  // --- diagnostics (spinner thread; FluidNodeDiagnostics.cpp) ---
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& status);
  void startDiagnostics();
  void publishDiagnostics();  // wall timer, every ~diagnostic_period
  std::string surfaceIdle(int subscribers) const;

  ros::NodeHandle nh_, pnh_;

  // Settings read once at start-up.
  std::string scenes_dir_;
  std::string world_frame_ = "world";
  std::string domain_frame_ = "fluid_domain";
  bool publish_clock_ = false;
  std::size_t max_particles_ = 1000000;
  HealthThresholds thresholds_;
  RobotSource robot_source_;
  double wrench_rate_ = 30.0;     // ~wrench/* [Hz]
  bool track_wrenches_ = false;   // measure wrenches even with no ~wrench subscriber (~stats)

  // ROS interface.
  ros::Publisher particles_pub_, stats_pub_, markers_pub_, clock_pub_;
  ros::ServiceServer reset_srv_, pause_srv_, step_srv_, emit_srv_;
  std::mutex tf_static_mutex_;          // guards tf_static_ (sim thread, render settings)
  tf2_ros::StaticTransformBroadcaster tf_static_;
  std::unique_ptr<diagnostic_updater::Updater> diagnostics_;
  ros::WallTimer diagnostics_timer_, master_timer_;
  double last_diagnostic_period_ = 0.0;  // the diagnostics timer's period [s]
  bool master_down_ = false;
  std::atomic<bool> master_lost_{false};
  std::function<void()> on_master_lost_;
  ReconfigureRecord record_;  // parameters the user set vs. those a previous run left
  // The private parameters as launched (without the record): a restarted master has lost
  // them, and gets them back before the node exits, so that a respawn starts the same scene.
  XmlRpc::XmlRpcValue launch_params_;
  bool restoreLaunchParams();  // onto a restarted master; false when a set failed
  boost::recursive_mutex reconfigure_mutex_;
  std::unique_ptr<ReconfigureServer> reconfigure_;

  // Reconfigure state (spinner thread, serialised by the reconfigure server).
  bool reconfigure_live_ = false;      // false while the server calls back during start-up
  FluidConfig applied_config_;         // what is in force
  pbf::Scene applied_scene_;           // the scene of applied_config_
  FluidConfig user_config_;            // parameters as the user set them (start-up, requests)
  std::set<std::string> user_param_names_;  // ... and which ones the user set
  RenderSettingsListener render_listener_;

  // Simulation thread state (set up in the constructor before the thread starts).
  std::unique_ptr<pbf::PbfSolver> solver_;
  pbf::Scene scene_;                   // what runs: the scene file's plus the robot's solids
  pbf::Scene scene_without_robot_;     // what a ~reset starts from (the URDF is read again)
  std::vector<RobotLinkSolids> robot_links_;  // which of scene_.obstacles are whose
  bool robot_built_once_ = false;      // later builds wait less for the links' tf
  RealTimePacer pacer_;
  std::atomic<bool> paused_{false};    // written by the simulation thread only
  bool stepped_since_resume_ = false;
  double sim_clock_ = 0.0;             // monotonic over resets: what /clock shows [s]
  pbf::StepStats last_stats_;
  std::uint32_t nan_recoveries_ = 0;   // since the last reset
  double publish_period_ = 1.0 / 30.0, stats_period_ = 0.1;
  double next_cloud_wall_ = 0.0, next_stats_wall_ = 0.0, next_snapshot_wall_ = 0.0;
  double last_clock_wall_ = 0.0;
  // Without ~publish_clock a stamp is stamp_anchor_ros_ + (sim_clock_ - stamp_anchor_sim_):
  // the ROS time [s] at which the simulation (re)started, plus the simulated time since. A
  // pair, not their difference: a clock restarted near 0 would make that negative.
  double stamp_anchor_ros_ = 0.0, stamp_anchor_sim_ = 0.0;
  ros::Subscriber clock_sub_;  // wakes the simulation thread when another node's /clock ticks
  // The anchor was taken on simulated time before any /clock came (ROS time 0): it is taken
  // again once one does, or stamps would count from 0 while /clock says otherwise.
  bool anchor_awaits_clock_ = false;
  RosClockJumps clock_jumps_;  // on the simulation thread
  std::uint64_t state_version_ = 0;    // changes with every step and rebuild
  std::uint64_t cloud_version_ = ~std::uint64_t(0);  // the state last published
  std::atomic<bool> cloud_wanted_{false};  // a new subscriber wants the current state
  double cloud_ms_ = 0.0;
  bool cloud_skipped_ = true;
  // Published as shared_ptr<const>; reused (no reallocation) once no subscriber holds it.
  boost::shared_ptr<sensor_msgs::PointCloud2> cloud_;
  SimulationTasks tasks_;
  SnapshotBuffer snapshots_;
  SurfaceRenderStatus surface_status_;
  std::unique_ptr<TfAttachments> attachments_;  // moves solids attached to tf frames
  std::unique_ptr<SolidWrenchPublishers> wrench_pubs_;  // ~wrench/<solid>
  pbf::FloatingBodies floating_;       // the scene's dynamic obstacles (moved after each step)
  pbf::FluidSources sources_;          // emitters, drains and ~emit, with their books
  double sources_since_wall_ = 0.0;    // when sources_ was (re)built [wall s]
  std::unique_ptr<ObstacleMover> mover_;  // rviz drags and ~obstacle_pose/* move free obstacles
  bool markers_stale_ = false;         // a moved obstacle: ~markers to be sent again
  double last_markers_wall_ = 0.0;
  std::unique_ptr<tf2_ros::TransformBroadcaster> floating_tf_;
  double last_floating_tf_wall_ = 0.0;
  TfStampGate floating_tf_stamps_;     // no floating pose twice at one stamp (paused resets)
  std::atomic<bool> running_{false};
  std::thread sim_thread_;

  // Rates on /diagnostics: ticked by the publishers, run by the diagnostics timer.
  TopicRateDiagnostic cloud_rate_, stats_rate_, image_rate_, depth_rate_;

  // Shared with the diagnostics callback.
  std::mutex health_mutex_;
  HealthSample health_;
};

}  // namespace pbf_ros
