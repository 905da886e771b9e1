// The surface render thread: GL context, latest snapshot, lazy rendering, publishing.
#include "pbf_ros/ros/SurfaceRenderThread.h"

#include <cerrno>
#include <chrono>
#include <cstring>
#include <boost/make_shared.hpp>
#include <pthread.h>
#include <sched.h>
#include <ros/package.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include "pbf_ros/render/FluidRenderer.h"
#include "pbf_ros/render/GlBackend.h"
#include "pbf_ros/ros/CameraInfoConversion.h"
#include "pbf_ros/ros/FluidNode.h"
#include "pbf_ros/ros/NodeParams.h"
#include "pbf_ros/ros/SurfaceImageConversion.h"
#include "pbf_ros/ros/WallThrottle.h"

namespace pbf_ros {

namespace {
using SteadyClock = std::chrono::steady_clock;
// How often an idle thread looks for subscribers (and new settings).
constexpr std::chrono::milliseconds kIdlePoll(100);
// How often a due frame looks for a snapshot it has not rendered yet.
constexpr std::chrono::milliseconds kSnapshotPoll(10);

// Identifies the fluid state of a snapshot: equal keys = the same particles in the same
// places (a paused simulation keeps writing snapshots of an unchanged state).
struct FluidStateKey {
  std::uint64_t step_count = ~0ull;
  double sim_time = -1.0;
  std::size_t size = 0;
  std::uint64_t hash = 0;
  bool operator==(const FluidStateKey& o) const {
    return step_count == o.step_count && sim_time == o.sim_time && size == o.size &&
           hash == o.hash;
  }
};

FluidStateKey fluidStateKey(const ParticleSnapshot& snapshot) {
  FluidStateKey key;
  key.step_count = snapshot.step_count;
  key.sim_time = snapshot.sim_time;
  key.size = snapshot.positions.size();
  // FNV-1a over the coordinates' bits: a reset or a scene change to the same step and time
  // still changes the positions.
  std::uint64_t h = 1469598103934665603ull;
  for (const Eigen::Vector3f& p : snapshot.positions) {
    for (int i = 0; i < 3; ++i) {
      std::uint32_t bits;
      std::memcpy(&bits, &p[i], sizeof(bits));
      h = (h ^ bits) * 1099511628211ull;
    }
  }
  key.hash = h;
  return key;
}

bool samePose(const geometry_msgs::TransformStamped& a, const geometry_msgs::TransformStamped& b) {
  const auto& p = a.transform.translation;
  const auto& q = b.transform.translation;
  const auto& r = a.transform.rotation;
  const auto& s = b.transform.rotation;
  return a.header.frame_id == b.header.frame_id && a.child_frame_id == b.child_frame_id &&
         p.x == q.x && p.y == q.y && p.z == q.z && r.x == s.x && r.y == s.y && r.z == s.z &&
         r.w == s.w;
}
}  // namespace

SurfaceStartup readSurfaceStartup(const ros::NodeHandle& private_nh) {
  SurfaceStartup s;
  private_nh.param<std::string>("render_backend", s.backend, s.backend);
  std::string default_shaders = ros::package::getPath("pbf_ros");
  if (!default_shaders.empty()) default_shaders += "/shaders";
  private_nh.param<std::string>("shader_dir", s.shader_dir, default_shaders);
  std::string warning, frame;
  auto warn = [&warning] {
    if (!warning.empty()) ROS_WARN("pbf_node: %s", warning.c_str());
  };
  // ~frame_id's warning is the node's (FluidNode::readNodeSettings), not repeated here.
  private_nh.param<std::string>("frame_id", frame, s.domain_frame);
  s.domain_frame = usableFrameId("frame_id", frame, s.domain_frame, warning);
  private_nh.param<std::string>("camera_frame_id", frame, s.camera_frame);
  s.camera_frame = usableFrameId("camera_frame_id", frame, s.camera_frame, warning);
  warn();
  // Linux adds at most 19 (and lowering it needs a privilege): more was 19 in silence.
  s.nice = static_cast<int>(withinRange("render_nice", readInteger(private_nh, "render_nice", s.nice), 0, 19,
                                        s.nice, warning));
  warn();
  s.idle_priority = readBool(private_nh, "render_idle_priority", s.idle_priority);
  return s;
}

SurfaceRenderThread::SurfaceRenderThread(ros::NodeHandle private_nh, const SurfaceStartup& startup,
                                         FluidNode& node)
    : startup_(startup),
      node_(node),
      snapshots_(node.snapshots()),
      status_(node.surfaceStatus()),
      transport_(private_nh) {
  // Every new connection (image or camera_info, any transport) gets a frame even when the
  // fluid has not changed since the last one (a paused simulation).
  const image_transport::SubscriberStatusCallback image_connected =
      [this](const image_transport::SingleSubscriberPublisher&) { onNewSubscriber(); };
  const ros::SubscriberStatusCallback info_connected =
      [this](const ros::SingleSubscriberPublisher&) { onNewSubscriber(); };
  image_pub_ = transport_.advertiseCamera("rgb/image_rect_color", 1, image_connected,
                                          image_transport::SubscriberStatusCallback(),
                                          info_connected, ros::SubscriberStatusCallback());
  depth_pub_ = transport_.advertiseCamera("depth_registered/image_rect", 1, image_connected,
                                          image_transport::SubscriberStatusCallback(),
                                          info_connected, ros::SubscriberStatusCallback());
  thread_ = std::thread(&SurfaceRenderThread::run, this);
}

SurfaceRenderThread::~SurfaceRenderThread() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void SurfaceRenderThread::onNewSubscriber() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++connections_;
  }
  wake_.notify_all();
}

void SurfaceRenderThread::configure(const FluidConfig& config,
                                    const Eigen::AlignedBox3f& container) {
  std::vector<std::string> notes;
  const SurfaceSettings settings = surfaceSettingsFromConfig(config, container, &notes);
  for (const std::string& note : notes) ROS_WARN("pbf_node: %s", note.c_str());
  const geometry_msgs::TransformStamped pose = toCameraTransform(
      settings.camera, startup_.domain_frame, startup_.camera_frame, ros::Time::now());
  bool moved = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    settings_ = settings;
    ++settings_generation_;
    moved = !configured_ || !samePose(pose, last_pose_);
    configured_ = true;
    last_pose_ = pose;
  }
  if (moved) node_.sendStaticTransform(pose);
  wake_.notify_all();
}

void SurfaceRenderThread::run() {
  pthread_setname_np(pthread_self(), "pbf_render");  // for top -H, ps -L (and the tests)
  if (startup_.nice != 0) {
    // Linux: the nice value belongs to the thread; threads started from here inherit it.
    const pid_t tid = static_cast<pid_t>(syscall(SYS_gettid));
    errno = 0;
    const int current = getpriority(PRIO_PROCESS, static_cast<id_t>(tid));
    if (errno != 0 ||
        setpriority(PRIO_PROCESS, static_cast<id_t>(tid), current + startup_.nice) != 0) {
      ROS_WARN("pbf_node: cannot lower the render thread's priority (~render_nice %d): %s",
               startup_.nice, std::strerror(errno));
    }
  }
  if (startup_.idle_priority) {
    // Inherited, like the nice value, by the GL threads created below.
    sched_param param{};
    param.sched_priority = 0;
    const int err = pthread_setschedparam(pthread_self(), SCHED_IDLE, &param);
    if (err != 0)
      ROS_WARN("pbf_node: cannot give the render thread idle priority (~render_idle_priority): %s",
               std::strerror(err));
  }
  std::unique_ptr<pbf::FluidRenderer> renderer;
  try {
    renderer = std::make_unique<pbf::FluidRenderer>(pbf::createGlBackend(startup_.backend),
                                                    startup_.shader_dir);
    ROS_INFO("pbf_node: surface renderer on '%s' (%s), shaders from %s", startup_.backend.c_str(),
             renderer->glDescription().c_str(), startup_.shader_dir.c_str());
  } catch (const std::exception& e) {
    ROS_ERROR("pbf_node: no surface rendering: cannot set up the '%s' GL back-end (~render_backend): "
              "%s. The simulation keeps running; the ~rgb and ~depth_registered images stay silent.",
              startup_.backend.c_str(), e.what());
    status_.unavailable = true;
  }

  // What was rendered last: a frame is rendered for a fluid that changed, new settings or a
  // new subscriber, never twice for the same state (a paused simulation costs nothing).
  FluidStateKey rendered_state;
  std::uint64_t rendered_generation = 0, rendered_connections = 0;
  auto next_frame = SteadyClock::now();
  std::unique_lock<std::mutex> lock(mutex_);
  while (!stop_) {
    const SurfaceSettings settings = settings_;
    const std::uint64_t generation = settings_generation_;
    const bool configured = configured_;
    const std::uint64_t connections = connections_;
    lock.unlock();

    const int image_count = static_cast<int>(image_pub_.getNumSubscribers());
    const int depth_count = static_cast<int>(depth_pub_.getNumSubscribers());
    status_.image_subscribers = image_count;
    status_.depth_subscribers = depth_count;
    const bool active = renderer && configured && (image_count > 0 || depth_count > 0);
    snapshots_.setRequestedRate(active ? settings.rate : 0.0);
    status_.active = active;
    if (!active) {
      status_.last_frame_ms = 0.0;
      rendered_state = FluidStateKey();
      lock.lock();
      wake_.wait_for(lock, kIdlePoll, [&] { return stop_; });
      next_frame = SteadyClock::now();
      continue;
    }

    auto now = SteadyClock::now();
    // A new subscriber or new settings (a faster render_rate, another size) get a frame now,
    // not when the old rate's period ends (at 0.1 Hz that was up to 10 s later).
    const bool newcomer = connections != rendered_connections;
    const bool new_settings = generation != rendered_generation;
    if (now >= next_frame || newcomer || new_settings) {
      const auto snapshot = snapshots_.latest();
      if (snapshot && !snapshot->positions.empty()) {
        const FluidStateKey state = fluidStateKey(*snapshot);
        if (newcomer || !(state == rendered_state) || new_settings) {
          if (new_settings) renderer->setOptions(settings.options);
          const bool early = now < next_frame;
          renderAndPublish(*renderer, *snapshot, settings, image_count > 0, depth_count > 0);
          rendered_state = state;
          rendered_generation = generation;
          rendered_connections = connections;
          // At most render_rate frames per second; a slow frame is not made up for.
          const auto period = std::chrono::duration_cast<SteadyClock::duration>(
              std::chrono::duration<double>(1.0 / std::max(settings.rate, 1e-3)));
          next_frame = early ? now + period : next_frame + period;
          now = SteadyClock::now();
          if (next_frame < now) next_frame = now;
        }
      }
    }
    // Sleep until the next frame is due; while one is due, look for a fresh snapshot often.
    auto wake = std::min(next_frame, now + kIdlePoll);
    if (wake <= now) wake = now + kSnapshotPoll;
    lock.lock();
    wake_.wait_until(lock, wake, [&] {
      return stop_ || settings_generation_ != generation || connections_ != connections;
    });
  }
  lock.unlock();
  snapshots_.setRequestedRate(0.0);
  status_.active = false;
  renderer.reset();  // the GL context is destroyed on the thread that owns it
}

void SurfaceRenderThread::renderAndPublish(pbf::FluidRenderer& renderer,
                                           const ParticleSnapshot& snapshot,
                                           const SurfaceSettings& settings, bool image,
                                           bool depth) {
  const auto start = SteadyClock::now();
  pbf::RenderRequest request;
  request.image = image;
  request.depth = depth;
  request.thickness = false;
  request.normals = false;
  try {
    const float radius = 0.5f * snapshot.particle_spacing;
    renderer.render(snapshot.positions, radius, settings.camera, request, out_,
                    snapshot.neighbor_counts.size() == snapshot.positions.size()
                        ? &snapshot.neighbor_counts
                        : nullptr);
  } catch (const std::exception& e) {
    PBF_ERROR_THROTTLE(5.0, "pbf_node: surface frame failed: %s", e.what());
    return;
  }

  std_msgs::Header header;
  header.stamp = ros::Time(snapshot.stamp);
  header.frame_id = startup_.camera_frame;
  // Fresh messages every frame: subscribers in this process may still hold the last ones.
  const auto info = boost::make_shared<const sensor_msgs::CameraInfo>(
      toCameraInfo(settings.camera, header));
  if (image) {
    auto msg = boost::make_shared<sensor_msgs::Image>();
    if (toColorImage(out_, header, *msg)) {
      image_pub_.publish(sensor_msgs::ImageConstPtr(msg), info);
      node_.imageRate().tick();
    }
  }
  if (depth) {
    auto msg = boost::make_shared<sensor_msgs::Image>();
    if (toDepthImage(out_, header, *msg)) {
      depth_pub_.publish(sensor_msgs::ImageConstPtr(msg), info);
      node_.depthRate().tick();
    }
  }
  status_.last_frame_ms =
      std::chrono::duration<double, std::milli>(SteadyClock::now() - start).count();
  ++status_.frames;
}

}  // namespace pbf_ros
