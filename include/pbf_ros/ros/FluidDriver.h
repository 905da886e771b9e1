#pragma once
// The whole fluid on the ROS graph: the simulation (FluidNode) and its surface render thread
// (SurfaceRenderThread), wired together. The one class behind both ways of running it:
// pbf_node (its own process, src/nodes/pbf_node.cpp) and pbf_ros/FluidNodelet (inside a
// nodelet manager, src/nodelet/FluidNodelet.cpp).
//
// Callbacks (services, reconfigure, diagnostics, subscriber connections) run on whatever
// spins the queues of `nh` and `private_nh`, which must have at least two threads: a
// service waits for the simulation thread while reconfigure or diagnostics are served.

#include <functional>

#include <ros/ros.h>

#include "pbf_ros/ros/FluidNode.h"
#include "pbf_ros/ros/SurfaceRenderThread.h"

namespace pbf_ros {

class FluidDriver {
 public:
  // Starts everything; throws std::runtime_error naming what is wrong (bad scene, bad
  // parameter) when the fluid cannot start. `on_master_lost` runs (on a callback thread)
  // when a restarted master has forgotten this node; see FluidNode::watchMaster.
  FluidDriver(ros::NodeHandle nh, ros::NodeHandle private_nh,
              std::function<void()> on_master_lost);
  // Stops the simulation thread, then joins the render thread (its frame in progress gets
  // the CPU the solver held).
  ~FluidDriver();
  FluidDriver(const FluidDriver&) = delete;
  FluidDriver& operator=(const FluidDriver&) = delete;

  bool masterLost() const { return node_.masterLost(); }

 private:
  FluidNode node_;
  SurfaceRenderThread surface_;  // after node_: it uses the node, and goes first
};

}  // namespace pbf_ros
