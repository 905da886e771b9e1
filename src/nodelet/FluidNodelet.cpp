// pbf_ros/FluidNodelet: the fluid (FluidDriver, the same class pbf_node runs) inside a
// nodelet manager, beside the user's own nodelets. Its messages go out as
// shared_ptr<const>, so nodelets in the same manager get the cloud and the images without a
// copy or serialisation.
#include <memory>
#include <stdexcept>

#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>

#include "pbf_ros/ros/FluidDriver.h"

namespace pbf_ros {

class FluidNodelet : public nodelet::Nodelet {
 public:
  ~FluidNodelet() override { driver_.reset(); }  // threads stop before the handles go

 private:
  void onInit() override {
    try {
      // The multi-threaded queue (the manager's worker pool): a service waits for the
      // simulation thread while reconfigure and diagnostics are served.
      driver_ = std::make_unique<FluidDriver>(getMTNodeHandle(), getMTPrivateNodeHandle(), [] {
        // The master forgot the whole manager process, not just this nodelet: nothing in it
        // is visible any more. End the process so that respawn can start it afresh.
        ros::requestShutdown();
      });
    } catch (const std::exception& e) {
      NODELET_FATAL("%s", e.what());
      // The manager refuses the load and `nodelet load` reports the failure.
      throw std::runtime_error("pbf_ros/FluidNodelet " + getName() + ": " + e.what());
    }
  }

  std::unique_ptr<FluidDriver> driver_;
};

}  // namespace pbf_ros

PLUGINLIB_EXPORT_CLASS(pbf_ros::FluidNodelet, nodelet::Nodelet)
