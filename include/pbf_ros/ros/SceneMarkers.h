#pragma once
// The scene's container as rviz markers (a wireframe box and a faint floor), in the fluid
// frame. Obstacles will join here when scenes have them.

#include <Eigen/Geometry>
#include <ros/time.h>
#include <string>
#include <visualization_msgs/MarkerArray.h>

namespace pbf_ros {

// The array starts with a DELETEALL so markers of a previous scene disappear.
visualization_msgs::MarkerArray makeContainerMarkers(const Eigen::AlignedBox3f& container,
                                                     const std::string& frame_id,
                                                     const ros::Time& stamp);

}  // namespace pbf_ros
