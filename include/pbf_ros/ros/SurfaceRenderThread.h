#pragma once
// The surface render thread of pbf_node (ARCHITECTURE.md section 4): it owns the GL context
// (created, used and destroyed on this thread only), takes the latest particle snapshot from
// the node's SnapshotBuffer (never blocking the solver) and publishes, laid out as an RGB-D
// camera for depth_image_proc (its point_cloud_xyzrgb takes these names as they are):
//   ~rgb/image_rect_color + ~rgb/camera_info                 (rgb8)
//   ~depth_registered/image_rect + ~depth_registered/camera_info  (32FC1 metres, NaN = none)
// with one shared header (the snapshot's stamp, frame fluid_camera_optical). "rect" and
// "registered" hold by construction: one ideal pinhole camera renders both, no distortion.
// Messages go out as shared_ptr<const> (zero copies to subscribers in the same process).
//
// Work only while someone listens: without a subscriber to either camera publisher the
// thread asks for no snapshots (the simulation copies nothing) and renders nothing. At most
// render_rate frames per second; when a frame takes longer, it simply renders less often.
// A frame is rendered only for a changed fluid, new settings or a newly connected
// subscriber: a paused simulation is rendered once, not over and over.
//
// A GL context that cannot be created is logged as an error naming the back-end; the
// simulation runs on without a surface.

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

#include <geometry_msgs/TransformStamped.h>
#include <image_transport/image_transport.h>
#include <ros/ros.h>

#include <pbf_ros/FluidConfig.h>

#include "pbf_ros/render/RenderOutput.h"
#include "pbf_ros/ros/RenderCameraParams.h"
#include "pbf_ros/ros/SnapshotBuffer.h"
#include "pbf_ros/ros/SurfaceRenderStatus.h"
#include "pbf_ros/ros/TopicRateDiagnostic.h"

namespace pbf {
class FluidRenderer;
}

namespace pbf_ros {

// Start-up parameters of the render thread (private namespace of the node).
struct SurfaceStartup {
  std::string backend = "osmesa";     // ~render_backend: osmesa | egl
  std::string shader_dir;             // ~shader_dir, default <package>/shaders
  std::string domain_frame = "fluid_domain";              // ~frame_id
  std::string camera_frame = "fluid_camera_optical";      // ~camera_frame_id
  // ~render_nice: niceness added to the render thread (and the GL threads it starts, e.g.
  // llvmpipe's), so that on a busy machine the solver gets the CPU first and the surface
  // is rendered less often, rather than the other way round. 0 = same priority.
  int nice = 10;
  // ~render_idle_priority: the render thread and the GL threads it starts run only on CPU
  // time the solver leaves idle (Linux SCHED_IDLE). A nice value alone did not protect the
  // solver: with OMP_WAIT_POLICY=passive its threads sleep at every barrier, and llvmpipe's
  // threads at nice 10 still took ~40 % of each core (the default scene's real-time factor
  // fell from 0.22 to 0.12 with the image subscribed; 0.20 with this). When the solver uses
  // every core, frames come less often instead (doc/performance.md).
  bool idle_priority = true;
};
SurfaceStartup readSurfaceStartup(const ros::NodeHandle& private_nh);

class FluidNode;

class SurfaceRenderThread {
 public:
  // Advertises the topics and starts the thread, which creates the GL context. Takes its
  // snapshots from `node`, reports into its surfaceStatus() and imageRate()/depthRate(),
  // and sends the camera pose through its one latched /tf_static publisher. `node` must
  // outlive this object.
  SurfaceRenderThread(ros::NodeHandle private_nh, const SurfaceStartup& startup, FluidNode& node);
  ~SurfaceRenderThread();  // stops the thread; the GL context dies with it
  SurfaceRenderThread(const SurfaceRenderThread&) = delete;
  SurfaceRenderThread& operator=(const SurfaceRenderThread&) = delete;

  // New render parameters (any thread; used from the next frame). `container` (fluid_domain)
  // places the automatic camera and the floor. Re-sends the camera transform when it moved.
  void configure(const FluidConfig& config, const Eigen::AlignedBox3f& container);

 private:
  void run();
  void onNewSubscriber();  // a subscriber connected (spinner thread)
  void renderAndPublish(pbf::FluidRenderer& renderer, const ParticleSnapshot& snapshot,
                        const SurfaceSettings& settings, bool image, bool depth);

  SurfaceStartup startup_;
  FluidNode& node_;
  SnapshotBuffer& snapshots_;
  SurfaceRenderStatus& status_;
  image_transport::ImageTransport transport_;
  image_transport::CameraPublisher image_pub_, depth_pub_;

  std::mutex mutex_;                   // guards what follows
  std::condition_variable wake_;
  bool stop_ = false;
  bool configured_ = false;
  std::uint64_t connections_ = 0;      // subscribers that ever connected
  SurfaceSettings settings_;
  std::uint64_t settings_generation_ = 0;
  geometry_msgs::TransformStamped last_pose_;

  pbf::RenderOutput out_;  // render thread only: buffers reused between frames

  std::thread thread_;
};

}  // namespace pbf_ros
