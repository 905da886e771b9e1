// pbf_node: a Position Based Fluids simulation on the ROS graph, in its own process. The
// same FluidDriver runs inside a nodelet manager as pbf_ros/FluidNodelet.
#include <ros/ros.h>

#include <exception>

#include "pbf_ros/ros/FluidDriver.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "fluid");
  // Held for the whole of main: the last NodeHandle to go shuts ROS down, logging with it,
  // and a start-up error must still be printed below.
  ros::NodeHandle nh, private_nh("~");
  bool master_lost = false;
  try {
    pbf_ros::FluidDriver fluid(nh, private_nh, [] { ros::requestShutdown(); });
    {
      // Two threads: a service may wait for the simulation thread while reconfigure or
      // diagnostics are served. Stopped (end of scope) before `fluid` goes away.
      ros::AsyncSpinner spinner(2);
      spinner.start();
      ros::waitForShutdown();
    }
    master_lost = fluid.masterLost();
  } catch (const std::exception& e) {
    ROS_FATAL("pbf_node: %s", e.what());
    return 1;
  }
  // A restarted master forgot this node: exit non-zero so that roslaunch's respawn can
  // start it afresh (README, "Master restart").
  return master_lost ? 2 : 0;
}
