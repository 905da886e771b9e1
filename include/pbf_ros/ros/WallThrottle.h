#pragma once
// Log throttling on the wall clock. rosconsole's ROS_*_THROTTLE measures its period on
// ros::Time, which here is often simulated: a /clock that steps back (a second publisher, a
// bag replayed with --clock) restarts every period, and a probe's flapping clock printed one
// warning 625 times in 12 s; on the node's own paused /clock a period never ends. These
// measure on std::chrono::steady_clock instead.

#include <atomic>
#include <chrono>
#include <cstdint>
#include <limits>

#include <ros/console.h>

namespace pbf_ros {

// True at most once per `period_s` of wall time for one call site's `last` (its previous
// admission, steady-clock ns). Two threads may both be admitted at once: a duplicate line
// at worst, as with rosconsole's own throttle.
inline bool wallThrottleAdmits(std::atomic<std::int64_t>& last, double period_s,
                               std::int64_t now_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                                   std::chrono::steady_clock::now().time_since_epoch()).count()) {
  const std::int64_t previous = last.load(std::memory_order_relaxed);
  if (previous != std::numeric_limits<std::int64_t>::min() &&
      static_cast<double>(now_ns - previous) < period_s * 1e9)
    return false;
  last.store(now_ns, std::memory_order_relaxed);
  return true;
}

}  // namespace pbf_ros

#define PBF_LOG_WALL_THROTTLE(level, period, ...)                                                      \
  do {                                                                                                 \
    static std::atomic<std::int64_t> pbf_wall_throttle_last_{std::numeric_limits<std::int64_t>::min()}; \
    if (::pbf_ros::wallThrottleAdmits(pbf_wall_throttle_last_, (period)))                               \
      ROS_LOG(level, ROSCONSOLE_DEFAULT_NAME, __VA_ARGS__);                                            \
  } while (false)
#define PBF_WARN_THROTTLE(period, ...) PBF_LOG_WALL_THROTTLE(::ros::console::levels::Warn, period, __VA_ARGS__)
#define PBF_ERROR_THROTTLE(period, ...) PBF_LOG_WALL_THROTTLE(::ros::console::levels::Error, period, __VA_ARGS__)
