// pbf_node: a Position Based Fluids simulation on the ROS graph. See FluidNode.h and
// SurfaceRenderThread.h.
#include <ros/ros.h>

#include <exception>

#include "pbf_ros/ros/FluidNode.h"
#include "pbf_ros/ros/SurfaceRenderThread.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "fluid");
  ros::NodeHandle nh;
  ros::NodeHandle private_nh("~");
  try {
    pbf_ros::FluidNode node(nh, private_nh);
    node.setMasterLostHandler([] { ros::requestShutdown(); });
    // The surface render thread: owns its GL context, reads node.snapshots() only while a
    // ~surface topic has subscribers, never blocks the simulation. A GL context that cannot
    // be created is logged; the simulation keeps running.
    pbf_ros::FluidNode& fluid = node;
    pbf_ros::SurfaceRenderThread surface(
        private_nh, pbf_ros::readSurfaceStartup(private_nh), node.snapshots(),
        node.surfaceStatus(),
        [&fluid](const geometry_msgs::TransformStamped& t) { fluid.sendStaticTransform(t); });
    node.setRenderSettingsListener(
        [&surface](const pbf_ros::FluidConfig& config, const pbf::Scene& scene) {
          surface.configure(config, scene.container);
        });
    {
      // Two threads: a service may wait for the simulation thread while reconfigure or
      // diagnostics are served. Stopped (end of scope) before `surface` goes away.
      ros::AsyncSpinner spinner(2);
      spinner.start();
      ros::waitForShutdown();
    }
    node.setRenderSettingsListener(nullptr);
    // A restarted master forgot this node: exit non-zero so that roslaunch's respawn can
    // start it afresh (README, "Master restart").
    if (node.masterLost()) return 2;
  } catch (const std::exception& e) {
    ROS_FATAL("pbf_node: %s", e.what());
    return 1;
  }
  return 0;
}
