#pragma once
// What the surface render thread reports to the simulation thread's ~stats: written by the
// render thread, read by anyone, lock-free.

#include <atomic>
#include <cstdint>

namespace pbf_ros {

struct SurfaceRenderStatus {
  // An image topic (~rgb, ~depth_registered) has a subscriber and the GL context works: frames are being rendered.
  std::atomic<bool> active{false};
  // Wall time of the last frame: render, read back, convert and publish [ms].
  std::atomic<double> last_frame_ms{0.0};
  // The GL context (or the shaders) could not be set up: no surface until a restart.
  std::atomic<bool> unavailable{false};
  // Frames rendered since the node started.
  std::atomic<std::uint64_t> frames{0};
  // Subscribers of the colour and the depth image (either counts camera_info too).
  std::atomic<int> image_subscribers{0};
  std::atomic<int> depth_subscribers{0};
};

}  // namespace pbf_ros
