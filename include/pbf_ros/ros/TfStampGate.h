#pragma once
// Lets a transform go out on tf only when its stamp differs from the last one sent for the
// same child frame. A tf2 buffer ignores a transform whose stamp it already holds for that
// frame, and says so (TF_REPEATED_DATA), in every listener, the node's own included. The
// node stamps what it publishes with the state's simulated time, and on its own /clock that
// time stands still whenever the state changes without a step: a reset or a scene switch
// while paused (simulated time goes on from where it was), or a second rebuild at start-up.
// Such a pose cannot reach tf at that stamp anyway; the next step publishes it.
//
// Plain (no master) so that it is unit-tested; one entry per child frame ever published
// (the scenes' floating bodies: a handful).

#include <map>
#include <string>

#include <ros/time.h>

namespace pbf_ros {

class TfStampGate {
 public:
  // True (and remembered) when `stamp` is not the last stamp admitted for `child_frame`.
  bool admit(const std::string& child_frame, const ros::Time& stamp);

 private:
  std::map<std::string, ros::Time> last_;
};

}  // namespace pbf_ros
