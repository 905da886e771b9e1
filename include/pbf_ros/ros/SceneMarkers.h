#pragma once
// A scene's solids as rviz markers: the container (wireframe box and a faint floor) and the
// obstacles. Solids attached to a tf frame are drawn in that frame, so rviz moves them
// with tf exactly as the solver does.

#include <geometry_msgs/Pose.h>
#include <ros/time.h>
#include <string>
#include <visualization_msgs/MarkerArray.h>

#include "pbf_ros/core/Scene.h"

namespace pbf_ros {

// The array starts with a DELETEALL so markers of a previous scene disappear.
// Namespaces: "container" (ids 0 edges, 1 floor), "obstacles" (ids from 0 upwards),
// "emitters" (an arrow per nozzle, id = its index, in its frame) and "drains" (the region,
// id = its index).
// A pose as a message (markers, interactive markers).
geometry_msgs::Pose poseMsg(const Eigen::Isometry3f& t);

visualization_msgs::MarkerArray makeSceneMarkers(const pbf::Scene& scene,
                                                 const std::string& domain_frame,
                                                 const ros::Time& stamp);

}  // namespace pbf_ros
