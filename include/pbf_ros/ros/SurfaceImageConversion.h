#pragma once
// pbf::RenderOutput -> sensor_msgs/Image: the shaded surface (rgb8; the renderer's opaque
// RGBA without its alpha) and its depth (32FC1,
// metres along the optical axis, NaN where there is no fluid: REP 118). Rows top-down, as
// the renderer gives them. Plain functions, unit-tested without a master.

#include <sensor_msgs/Image.h>
#include <std_msgs/Header.h>

#include "pbf_ros/render/RenderOutput.h"

namespace pbf_ros {

// Returns false (and leaves `image` alone) when `out` holds no colour image.
bool toColorImage(const pbf::RenderOutput& out, const std_msgs::Header& header,
                  sensor_msgs::Image& image);

// Returns false (and leaves `image` alone) when `out` holds no depth image.
bool toDepthImage(const pbf::RenderOutput& out, const std_msgs::Header& header,
                  sensor_msgs::Image& image);

}  // namespace pbf_ros
