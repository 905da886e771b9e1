// The simulation thread: steps the solver at the requested real-time factor, publishes what
// is due, and runs queued changes between steps. Everything here owns the solver; nothing
// here waits for a ROS callback.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <sstream>
#include <stdexcept>
#include <boost/make_shared.hpp>
#include <rosgraph_msgs/Clock.h>

#include "pbf_ros/ros/CloudConversion.h"
#include "pbf_ros/ros/DomainTransform.h"
#include "pbf_ros/ros/FluidNode.h"
#include "pbf_ros/ros/SceneMarkers.h"
#include "pbf_ros/ros/SolidWrenchTargets.h"
#include "pbf_ros/ros/StatsConversion.h"
#include "pbf_ros/ros/WallThrottle.h"
#include "pbf_ros/core/SceneSetup.h"

namespace pbf_ros {

namespace {
using SteadyClock = std::chrono::steady_clock;

SteadyClock::time_point toSteady(double seconds) {
  return SteadyClock::time_point(std::chrono::duration_cast<SteadyClock::duration>(
      std::chrono::duration<double>(seconds)));
}

// Next due time of a periodic job that just ran at `wall`: keeps the phase (no drift)
// unless the job fell a whole period behind.
double nextDue(double due, double period, double wall) {
  due += period;
  return due <= wall ? wall + period : due;
}

constexpr double kPausedWakeup = 0.05;     // [s] while paused: tasks, /clock, publications
constexpr double kMinClockPeriod = 0.001;  // /clock at most 1 kHz (as-fast-as-possible runs)
constexpr double kMaxTfWait = 0.02;        // [wall s] for a frame publisher behind the step
// On another node's /clock ROS time moves only when a clock message comes, and each wakes
// the simulation thread (clock_sub_); this bounds the wait should that wake-up come before
// roscpp has taken the new time [wall s].
constexpr double kClockPoll = 0.01;
}  // namespace

double FluidNode::wallNow() const {
  return std::chrono::duration<double>(SteadyClock::now().time_since_epoch()).count();
}

bool FluidNode::followsRosClock() const { return !publish_clock_ && ros::Time::isSimTime(); }

double FluidNode::pacingNow() const {
  return followsRosClock() ? ros::Time::now().toSec() : wallNow();
}

// Every message about a state carries that state's simulated time. With ~publish_clock the
// node is the clock: the stamp is /clock's time. Without it, the stamp is the ROS time at
// which the simulation (re)started plus the simulated time since: below real time the
// stamps fall behind the wall clock, but differences between them are simulated seconds.
ros::Time FluidNode::stamp() const {
  // Never below 0, which ros::Time refuses by throwing (a drop's kept tick on a clock that
  // has just started at 0).
  return publish_clock_ ? ros::Time(sim_clock_)
                        : ros::Time(std::max(0.0, stamp_anchor_ros_ + (sim_clock_ - stamp_anchor_sim_)));
}

void FluidNode::anchorStamps() {
  const ros::Time now = ros::Time::now();
  anchor_awaits_clock_ = now.isZero();  // use_sim_time, and no /clock yet
  stamp_anchor_ros_ = now.toSec();
  stamp_anchor_sim_ = sim_clock_;
}

void FluidNode::anchorStampsAtPacerTarget(double clock_now) {
  stamp_anchor_ros_ = clock_now;
  stamp_anchor_sim_ = pacer_.targetSim(clock_now);
}

void FluidNode::followClockJumps() {
  const ros::Time now = ros::Time::now();
  const double jump = clock_jumps_.update(now.toSec(), wallNow());
  if (jump == 0.0) return;
  anchorStamps();
  if (followsRosClock()) {
    // Back, the fluid would stand until the clock came round again; ahead, it would race to
    // catch up. It goes on from now, with the leap's worth up to a tick's (kMaxTickKept) still
    // to simulate: a bag at 20x ticks 2 s at a time, which looks like a leap, and restarted
    // at each tick it never stepped. Its stamps reach the clock's when that is done.
    const double kept = jump > 0.0 ? std::min(jump, RealTimePacer::kMaxTickKept) : 0.0;
    pacer_.restart(now.toSec() - kept, sim_clock_);
    anchorStampsAtPacerTarget(now.toSec());
  }
  // Throttled: two /clock publishers at once jump back and forth at every message.
  PBF_WARN_THROTTLE(10.0, "pbf_node: ROS time jumped %s by %.6g s (a /clock that restarted, a bag that "
                    "looped, a system clock that was set, two /clock publishers?): stamps continue "
                    "from %.6f s", jump < 0.0 ? "back" : "ahead", std::abs(jump), now.toSec());
}

void FluidNode::runSimulation() {
  while (running_ && ros::ok()) {
    tasks_.runAll();
    if (anchor_awaits_clock_ && !publish_clock_ && !ros::Time::now().isZero()) {
      anchorStamps();
      if (followsRosClock()) pacer_.restart(pacingNow(), sim_clock_);  // the clock has come
    }
    if (!publish_clock_ && !anchor_awaits_clock_) followClockJumps();
    const double wall = wallNow();
    // On another node's /clock nothing moves until it runs (ROS time 0 until then).
    const bool clock_awaited = followsRosClock() && anchor_awaits_clock_;
    const double pace = pacingNow();
    if (!paused_ && !clock_awaited && pacer_.shouldStep(pace, sim_clock_)) {
      stepOnce();
      publishDue(wallNow(), /*force=*/false);
      continue;
    }
    publishDue(wall, /*force=*/false);
    if (paused_) publishClock();

    // Sleep until the next step or publication is due, or until a task arrives.
    double wake = std::min(next_cloud_wall_, next_stats_wall_);
    if (paused_) {
      wake = std::min(wake, wall + kPausedWakeup);
    } else if (followsRosClock()) {
      wake = std::min(wake, wall + kClockPoll);  // or the next clock message
    } else {
      wake = std::min(wake, pacer_.wallTimeDue(sim_clock_) + 1e-6);
    }
    if (snapshots_.requestedRate() > 0.0) wake = std::min(wake, next_snapshot_wall_);
    if (wake > wall) tasks_.waitUntil(toSteady(wake));
  }
}

void FluidNode::stepOnce() {
  if (!attachments_) attachments_ = std::make_unique<TfAttachments>(domain_frame_);
  try {
    // On the node's own /clock, frame publishers stamp with simulated time: look up the
    // pose at this step's time and wait a little for a publisher that is behind. On the
    // wall clock the step's stamp lags real time below real-time speed: take the latest.
    const ros::Time time = publish_clock_ ? stamp() : ros::Time(0);
    const TfAttachments::Report tf = attachments_->update(scene_, *solver_, time, kMaxTfWait);
    if (!tf.missing.empty()) {
      PBF_WARN_THROTTLE(10.0, "pbf_node: no tf for frame '%s' (%s -> it) yet; its solid stays put",
                        tf.missing.front().c_str(), domain_frame_.c_str());
    }
    if (!tf.non_finite.empty()) {
      PBF_WARN_THROTTLE(10.0, "pbf_node: frame '%s' has a non-finite pose in tf (%s -> it); its solid "
                        "keeps its previous pose", tf.non_finite.front().c_str(), domain_frame_.c_str());
    }
    if (!tf.behind.empty()) {
      PBF_WARN_THROTTLE(10.0, "pbf_node: frame '%s': its latest pose is %.3g simulated s old and its next "
                        "is overdue; its solid holds the latest (is its publisher on /clock, and alive?)",
                        tf.behind.front().first.c_str(), tf.behind.front().second);
    }
  } catch (const std::exception& e) {  // a non-finite pose: keep the previous one
    PBF_WARN_THROTTLE(10.0, "pbf_node: ignoring an attached frame's pose: %s", e.what());
  }
  // Obstacles a user drags (rviz, ~obstacle_pose/*) take their next bounded step.
  markers_stale_ = mover_->apply(*solver_, scene_) || markers_stale_;
  // Wrenches are measured only while someone wants them (a ~wrench subscriber) or a body
  // floats on them.
  solver_->setWrenchTracking(wrench_pubs_->wanted());
  floating_.prepare(*solver_);
  const double time_before = solver_->time();
  last_stats_ = solver_->step();
  if (!last_stats_.failed) {
    wrench_pubs_->accumulate(scene_, *solver_, last_stats_.dt);  // at the poses of the step
    // Poses for the next step.
    if (const std::size_t stuck = floating_.afterStep(*solver_, last_stats_.dt)) {
      PBF_WARN_THROTTLE(10.0, "pbf_node: %zu floating bodies held at rest: the fluid's push would have "
                        "moved them beyond any finite pose", stuck);
    }
    publishFloatingPoses();
    applySources(last_stats_.dt);  // the particle count may change here, between steps
  }
  if (!solver_->wrenchTracking()) last_stats_.skipped_stages.add(pbf::SkippedStages::kWrench);
  sim_clock_ += solver_->time() - time_before;
  ++state_version_;
  nan_recoveries_ += static_cast<std::uint32_t>(last_stats_.nan_retries);
  stepped_since_resume_ = true;
  const double wall = wallNow(), pace = pacingNow();
  if (paused_) {
    pacer_.restart(pace, sim_clock_);  // a ~step while paused is not a pacing sample
  } else {
    const double dropped = pacer_.droppedSimTime();
    pacer_.afterStep(pace, sim_clock_, wall);
    // On another node's clock the fluid keeps that clock's time: what it could not simulate
    // is skipped, and its stamps go on from the clock. (On the wall clock they fall behind
    // instead, so that differences between stamps stay simulated seconds.)
    if (followsRosClock() && pacer_.droppedSimTime() > dropped) anchorStampsAtPacerTarget(pace);
  }
  if (!paused_ && pacer_.factor() > 0.0 && pacer_.settled() &&
      pacer_.achievedFactor() < thresholds_.rtf_warn_ratio * pacer_.factor()) {
    PBF_WARN_THROTTLE(10.0, "pbf_node: cannot keep up with real-time factor %g: achieving %.3g",
                      pacer_.factor(), pacer_.achievedFactor());
  }
  if (last_stats_.failed && last_stats_.dense_retries > 0) {
    PBF_ERROR_THROTTLE(5.0, "pbf_node: step %llu given up after %d retries with half the time step, "
                       "%d of them because the particles are packed far denser than a fluid (more "
                       "than %zu neighbour pairs): the fluid has collapsed, most likely a time step "
                       "too long for the forces (time_step, gravity); state kept, ~reset starts again",
                       static_cast<unsigned long long>(solver_->stepCount()), last_stats_.nan_retries,
                       last_stats_.dense_retries, solver_->neighborPairBound());
  } else if (last_stats_.dense_retries > 0) {  // retried, then succeeded
    PBF_WARN_THROTTLE(10.0, "pbf_node: step %llu retried with a shorter time step %d times because the "
                      "particles were packed far denser than a fluid (more than %zu neighbour pairs): "
                      "the time step is too long for the forces (time_step, gravity)",
                      static_cast<unsigned long long>(solver_->stepCount()), last_stats_.dense_retries,
                      solver_->neighborPairBound());
  } else if (last_stats_.failed) {
    PBF_ERROR_THROTTLE(5.0, "pbf_node: step %llu given up after %d NaN retries; state kept",
                       static_cast<unsigned long long>(solver_->stepCount()),
                       last_stats_.nan_retries);
  }
  {
    std::lock_guard<std::mutex> lock(health_mutex_);
    health_.nan_recoveries_recent += static_cast<std::uint32_t>(last_stats_.nan_retries);
    health_.failed_steps_recent += last_stats_.failed ? 1u : 0u;
    health_.steps_recent += 1u;
    health_.capped_steps_recent += last_stats_.iteration_cap_reached ? 1u : 0u;
  }
  updateHealth();
  publishClock();
  if (markers_stale_ && wall - last_markers_wall_ >= 0.1) {  // at most 10 Hz while moving
    last_markers_wall_ = wall;
    markers_stale_ = false;
    markers_pub_.publish(makeSceneMarkers(scene_, domain_frame_, stamp()));
  }
}

void FluidNode::publishDue(double wall, bool force) {
  if (force || wall >= next_cloud_wall_) {
    next_cloud_wall_ = nextDue(next_cloud_wall_, publish_period_, wall);
    publishCloud(force);
  }
  if (force || wall >= next_stats_wall_) {
    next_stats_wall_ = nextDue(next_stats_wall_, stats_period_, wall);
    publishStats();
  }
  wrench_pubs_->publishDue(wall, stamp());
  const double snapshot_rate = snapshots_.requestedRate();
  // A faster rate takes effect within its own period, not after the slower one's.
  if (snapshot_rate > 0.0) next_snapshot_wall_ = std::min(next_snapshot_wall_, wall + 1.0 / snapshot_rate);
  if (snapshot_rate > 0.0 && (force || wall >= next_snapshot_wall_)) {
    next_snapshot_wall_ = nextDue(next_snapshot_wall_, 1.0 / snapshot_rate, wall);
    snapshots_.write(*solver_, stamp().toSec(), solver_->time());
  }
}

void FluidNode::publishCloud(bool force) {
  // Lazy: nobody listens, nothing is built (stats report "cloud" as skipped).
  if (particles_pub_.getNumSubscribers() == 0) {
    cloud_skipped_ = true;
    cloud_ms_ = 0.0;
    return;
  }
  // A state is published once, except to someone who just subscribed (paused fluid).
  const bool wanted = cloud_wanted_.exchange(false);
  if (!force && !wanted && cloud_version_ == state_version_) return;
  cloud_version_ = state_version_;
  const auto start = SteadyClock::now();
  // Subscribers in this process (nodelets) hold the very object published: fill a fresh
  // one unless they have all let go of the last (then its buffer is reused).
  if (!cloud_ || !cloud_.unique()) cloud_ = boost::make_shared<sensor_msgs::PointCloud2>();
  cloud_->header.stamp = stamp();
  cloud_->header.frame_id = domain_frame_;
  const std::size_t dropped = fillParticleCloud(solver_->positions(), solver_->velocities(),
                                                solver_->densities(), solver_->ids(), *cloud_);
  if (dropped > 0) {
    PBF_ERROR_THROTTLE(5.0, "pbf_node: %zu particles with non-finite values left out of ~particles",
                       dropped);
  }
  particles_pub_.publish(boost::shared_ptr<const sensor_msgs::PointCloud2>(cloud_));
  cloud_rate_.tick();
  cloud_ms_ = std::chrono::duration<double, std::milli>(SteadyClock::now() - start).count();
  cloud_skipped_ = false;
}

void FluidNode::publishStats() {
  if (stats_pub_.getNumSubscribers() == 0) return;
  StatsContext context;
  context.stamp = stamp();
  context.frame_id = domain_frame_;
  context.sim_time = solver_->time();
  context.step_count = solver_->stepCount();
  context.particle_count = static_cast<std::uint32_t>(solver_->size());
  context.real_time_factor = paused_ ? 0.0 : pacer_.achievedFactor();
  context.nan_recoveries = nan_recoveries_;
  context.cloud_ms = cloud_ms_;
  context.cloud_skipped = cloud_skipped_;
  context.render_skipped = !surface_status_.active.load();
  context.render_ms = surface_status_.last_frame_ms.load();
  context.render_frames = surface_status_.frames.load();
  context.wrench_tracked = wrench_pubs_->takeTotal(context.solids_wrench);
  context.initial_particle_count = static_cast<std::uint32_t>(sources_.initialParticles());
  context.particles_emitted = sources_.emitted();
  context.particles_drained = sources_.drained();
  context.particle_mass = solver_->params().particleMass();
  stats_pub_.publish(boost::make_shared<const SimulationStats>(toStatsMessage(last_stats_, context)));
  stats_rate_.tick();
}

void FluidNode::publishClock() {
  if (!publish_clock_) return;
  const double wall = wallNow();
  if (wall - last_clock_wall_ < kMinClockPeriod) return;
  last_clock_wall_ = wall;
  rosgraph_msgs::Clock clock;
  clock.clock = ros::Time(sim_clock_);
  clock_pub_.publish(clock);
}

std::string FluidNode::rebuildFluid(const pbf::Scene& scene, const pbf::SolverParams& params) {
  try {
    pbf::Scene next = scene;
    next.solver = params;
    // Counted before anything is allocated: a fine spacing must not take gigabytes first.
    std::string why = next.validate();
    if (!why.empty()) return why;
    std::vector<RobotLinkSolids> robot_links = addRobotSolids(next);
    why = next.checkParticleCount(max_particles_);
    if (!why.empty()) return why;
    // A fresh solver: time and step count start again from 0; the old one keeps running
    // if anything below throws.
    auto fresh = std::make_unique<pbf::PbfSolver>();
    pbf::setUpSolver(next, *fresh);  // parameters, container, obstacles, particles
    seedAtCurrentPoses(next, *fresh);
    pbf::FloatingBodies floating = pbf::makeFloatingBodies(next);
    pbf::FluidSources sources(next.emitters, next.drains, fresh->size());
    solver_ = std::move(fresh);
    sources_ = std::move(sources);
    sources_since_wall_ = wallNow();
    scene_ = next;
    scene_without_robot_ = scene;
    scene_without_robot_.solver = params;
    robot_links_ = std::move(robot_links);
    floating_ = std::move(floating);
    wrench_pubs_->setTargets(wrenchTargets(scene_, robot_links_, domain_frame_));
    std::vector<std::size_t> robot_obstacles;
    for (const RobotLinkSolids& link : robot_links_)
      robot_obstacles.insert(robot_obstacles.end(), link.obstacles.begin(), link.obstacles.end());
    mover_->setScene(scene_, robot_obstacles);
  } catch (const std::exception& e) {
    return e.what();
  }
  ++state_version_;
  if (attachments_) attachments_->restart();
  anchorStamps();
  last_stats_ = pbf::StepStats();
  last_stats_.particle_count = static_cast<std::uint32_t>(solver_->size());
  nan_recoveries_ = 0;
  stepped_since_resume_ = false;
  pacer_.restart(pacingNow(), sim_clock_);
  next_cloud_wall_ = next_stats_wall_ = next_snapshot_wall_ = 0.0;  // publish promptly
  announceScene();
  last_floating_tf_wall_ = 0.0;
  publishFloatingPoses();
  updateHealth();
  return "";
}

// Floating bodies' poses on tf (fluid_domain -> their frame), at most every 10 ms of wall
// time: rviz draws their markers there, and other nodes can follow them.
void FluidNode::publishFloatingPoses() {
  if (floating_.empty()) return;
  const double wall = wallNow();
  if (wall - last_floating_tf_wall_ < 0.01) return;
  last_floating_tf_wall_ = wall;
  if (!floating_tf_) floating_tf_ = std::make_unique<tf2_ros::TransformBroadcaster>();
  const ros::Time now = stamp();
  for (const auto& [index, body] : floating_.bodies()) {
    const Eigen::Isometry3f& pose = body.shape().pose;
    if (!pose.matrix().allFinite() || index >= scene_.obstacles.size()) continue;
    // A rebuild while paused on /clock comes at the stamp the last step sent (TfStampGate).
    if (!floating_tf_stamps_.admit(scene_.obstacles[index].frame, now)) continue;
    geometry_msgs::TransformStamped t;
    t.header.stamp = now;
    t.header.frame_id = domain_frame_;
    t.child_frame_id = scene_.obstacles[index].frame;
    t.transform.translation.x = pose.translation().x();
    t.transform.translation.y = pose.translation().y();
    t.transform.translation.z = pose.translation().z();
    const Eigen::Quaternionf q(pose.linear());
    t.transform.rotation.x = q.x();
    t.transform.rotation.y = q.y();
    t.transform.rotation.z = q.z();
    t.transform.rotation.w = q.w();
    floating_tf_->sendTransform(t);
  }
}

// A reset or scene switch while attached frames have moved: the container, the obstacles
// and the fluid blocks given in those frames start where the frames are now (water in the
// tilted cup, not where the upright cup stood). Frames tf does not know stay at rest.
void FluidNode::seedAtCurrentPoses(const pbf::Scene& scene, pbf::PbfSolver& solver) {
  if (!TfAttachments::needed(scene)) return;
  if (!attachments_) attachments_ = std::make_unique<TfAttachments>(domain_frame_);
  std::map<std::string, Eigen::Isometry3f> poses;
  auto poseOf = [&](const std::string& frame) -> const Eigen::Isometry3f* {
    if (frame.empty()) return nullptr;
    auto it = poses.find(frame);
    if (it == poses.end()) {
      Eigen::Isometry3f pose;
      if (!attachments_->currentPose(frame, pose)) return nullptr;
      it = poses.emplace(frame, pose).first;
    }
    return &it->second;
  };
  if (const auto* pose = poseOf(scene.container_frame)) solver.setContainerPose(*pose);
  for (std::size_t k = 0; k < scene.obstacles.size(); ++k)
    if (const auto* pose = scene.floats(k) ? nullptr : poseOf(scene.obstacles[k].frame))
      solver.setObstaclePose(k, *pose * scene.obstacles[k].offset);
  bool moved = false;
  for (std::size_t b = 0; b < scene.fluid.size(); ++b) moved = moved || poseOf(scene.blockFrame(b));
  if (!moved) return;
  std::vector<Eigen::Vector3f> x, v;
  std::vector<std::uint32_t> block_of;
  scene.initialParticles(x, v, &block_of);
  // A frame may have taken its block out of the container (a cup lifted away, turned over
  // the floor): those particles are left out, with a warning. Clamped into the container
  // they started piled on its walls and burst out at 18 m/s.
  const Eigen::Isometry3f to_container = solver.containerPose().inverse();
  const Eigen::AlignedBox3f& box = solver.container();
  std::vector<std::size_t> outside(scene.fluid.size(), 0), total(scene.fluid.size(), 0);
  std::size_t kept = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const std::uint32_t b = block_of[i];
    if (const auto* pose = poseOf(scene.blockFrame(b))) {
      x[i] = *pose * x[i];
      v[i] = pose->linear() * v[i];
    }
    ++total[b];
    if (!box.contains(to_container * x[i])) {
      ++outside[b];
      continue;
    }
    x[kept] = x[i], v[kept] = v[i];
    ++kept;
  }
  x.resize(kept), v.resize(kept);
  auto whereIs = [&](std::size_t b) {
    std::ostringstream where;
    where << "fluid[" << b << "] in frame '" << scene.blockFrame(b) << "'";
    if (const auto* pose = poseOf(scene.blockFrame(b)))
      where << " (now at " << pose->translation().transpose() << " m)";
    return where.str();
  };
  for (std::size_t b = 0; b < scene.fluid.size(); ++b)
    if (outside[b] > 0 && kept > 0)
      ROS_WARN("pbf_node: %s: %zu of its %zu particles would start outside the container; left out",
               whereIs(b).c_str(), outside[b], total[b]);
  if (kept == 0) {
    std::size_t b = 0;
    while (b + 1 < outside.size() && outside[b] == 0) ++b;
    throw std::runtime_error("every particle would start outside the container where the fluid's "
                             "frames are now (" + whereIs(b) + ")");
  }
  solver.setParticles(x, v);
}

void FluidNode::announceScene() {
  const ros::Time now = stamp();
  markers_pub_.publish(makeSceneMarkers(scene_, domain_frame_, now));
  sendStaticTransform(makeDomainTransform(scene_, world_frame_, domain_frame_, now));
}

void FluidNode::setRates(double publish_rate, double stats_rate) {
  publish_period_ = 1.0 / std::max(publish_rate, 1e-3);
  stats_period_ = 1.0 / std::max(stats_rate, 1e-3);
  const double wall = wallNow();
  next_cloud_wall_ = std::min(next_cloud_wall_, wall + publish_period_);
  next_stats_wall_ = std::min(next_stats_wall_, wall + stats_period_);
}

void FluidNode::updateHealth() {
  std::lock_guard<std::mutex> lock(health_mutex_);
  health_.scene = scene_.name;
  health_.paused = paused_;
  health_.running = stepped_since_resume_ && pacer_.settled();
  health_.requested_factor = pacer_.factor();
  health_.achieved_factor = paused_ ? 0.0 : pacer_.achievedFactor();
  health_.sim_time = solver_->time();
  health_.step_count = solver_->stepCount();
  health_.particle_count = static_cast<std::uint32_t>(solver_->size());
  health_.avg_density_error = last_stats_.avg_density_error;
  health_.max_density_error = last_stats_.max_density_error;
  health_.max_speed = last_stats_.max_speed;
  health_.iterations = last_stats_.iterations;
  health_.max_iterations = solver_->params().max_iterations;
  health_.dt = last_stats_.dt;
  health_.nan_recoveries_total = nan_recoveries_;
}

}  // namespace pbf_ros
