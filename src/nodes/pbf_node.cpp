// pbf_node: a Position Based Fluids simulation on the ROS graph. See FluidNode.h.
#include <ros/ros.h>

#include <exception>

#include "pbf_ros/ros/FluidNode.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "fluid");
  ros::NodeHandle nh;
  ros::NodeHandle private_nh("~");
  try {
    pbf_ros::FluidNode node(nh, private_nh);
    // A surface render thread plugs in here: construct it with node.snapshots() (it sets
    // a requested rate while its topics have subscribers and reads latest()); it owns its
    // GL context and never blocks the simulation.
    // Two threads: a service may wait for the simulation thread while reconfigure or
    // diagnostics are served.
    ros::AsyncSpinner spinner(2);
    spinner.start();
    ros::waitForShutdown();
  } catch (const std::exception& e) {
    ROS_FATAL("pbf_node: %s", e.what());
    return 1;
  }
  return 0;
}
