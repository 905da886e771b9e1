#pragma once
// The static transform world -> fluid_domain of a scene.

#include <geometry_msgs/TransformStamped.h>
#include <ros/time.h>
#include <string>

#include "pbf_ros/core/Scene.h"

namespace pbf_ros {

geometry_msgs::TransformStamped makeDomainTransform(const pbf::Scene& scene,
                                                    const std::string& world_frame,
                                                    const std::string& domain_frame,
                                                    const ros::Time& stamp);

}  // namespace pbf_ros
