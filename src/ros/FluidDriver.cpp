#include "pbf_ros/ros/FluidDriver.h"

namespace pbf_ros {

FluidDriver::FluidDriver(ros::NodeHandle nh, ros::NodeHandle private_nh,
                         std::function<void()> on_master_lost)
    : node_(nh, private_nh),
      // Owns its GL context; reads the node's snapshots only while an image has a
      // subscriber; never blocks the simulation. A GL context that cannot be created is
      // logged, and the simulation keeps running.
      surface_(private_nh, readSurfaceStartup(private_nh), node_) {
  node_.setMasterLostHandler(std::move(on_master_lost));
  node_.setRenderSettingsListener([this](const FluidConfig& config, const pbf::Scene& scene) {
    surface_.configure(config, scene.container);
  });
}

FluidDriver::~FluidDriver() {
  // Reconfigure must not reach the render thread once it is going away.
  node_.setRenderSettingsListener(nullptr);
  // The solver first: the render thread runs at idle priority and, joined while the solver
  // still held both cores, took 0.5-5 s to finish its frame (a nodelet's unload).
  node_.stopSimulation();
}

}  // namespace pbf_ros
