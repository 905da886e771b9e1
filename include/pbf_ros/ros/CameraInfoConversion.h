#pragma once
// pbf::RenderCamera -> sensor_msgs/CameraInfo and the fluid_domain -> fluid_camera_optical
// transform. K and P come from pbf::intrinsicsOf, the pinhole model the GL projection
// realises pixel for pixel, so a point projected with K lands where the renderer drew it.
// Plain functions, unit-tested without a master.

#include <geometry_msgs/TransformStamped.h>
#include <sensor_msgs/CameraInfo.h>
#include <std_msgs/Header.h>
#include <string>

#include "pbf_ros/render/RenderCamera.h"

namespace pbf_ros {

// plumb_bob with zero distortion, R = identity, P = [K | 0], no binning, full-image ROI.
sensor_msgs::CameraInfo toCameraInfo(const pbf::RenderCamera& camera,
                                     const std_msgs::Header& header);

// The camera's pose (optical convention: z forward, x right, y down) as the transform
// parent_frame (the fluid frame the particles are in) -> camera_frame.
geometry_msgs::TransformStamped toCameraTransform(const pbf::RenderCamera& camera,
                                                  const std::string& parent_frame,
                                                  const std::string& camera_frame,
                                                  const ros::Time& stamp);

}  // namespace pbf_ros
