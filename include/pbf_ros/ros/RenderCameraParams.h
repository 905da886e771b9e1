#pragma once
// Fluid.cfg's render parameters -> what the surface render thread needs: the camera (pose in
// fluid_domain, image size, field of view), the renderer's options and the frame rate.
// Plain functions, unit-tested without a master.

#include <Eigen/Geometry>
#include <set>
#include <string>
#include <vector>

#include <pbf_ros/FluidConfig.h>

#include "pbf_ros/render/RenderCamera.h"
#include "pbf_ros/render/RenderOptions.h"

namespace pbf_ros {

struct SurfaceSettings {
  pbf::RenderCamera camera;     // camera_to_world: fluid_camera_optical in fluid_domain
  pbf::RenderOptions options;
  double rate = 10.0;           // [Hz]
};

// The automatic camera: looks at the container's centre from the front-right, above
// (azimuth -60 deg from +x, elevation 30 deg), image up = +z, as close as it can while every
// corner of the container stays in the image (with a 5 % margin).
Eigen::Isometry3f frameContainer(const Eigen::AlignedBox3f& container, float vertical_fov,
                                 int width, int height);

// Camera pose, size and field of view from the config; camera_auto frames `container`.
// Near/far clips follow the distance to the container.
pbf::RenderCamera renderCameraFromConfig(const FluidConfig& config,
                                         const Eigen::AlignedBox3f& container);

// Whether `name` is one of Fluid.cfg's render_filter choices (narrow_range, bilateral, none).
bool knownRenderFilter(const std::string& name);

// Filter and drawing options. The floor is drawn at the container's bottom. An unknown
// render_filter falls back to narrow_range with a note in `notes` (if given).
pbf::RenderOptions renderOptionsFromConfig(const FluidConfig& config,
                                           const Eigen::AlignedBox3f& container,
                                           std::vector<std::string>* notes = nullptr);

SurfaceSettings surfaceSettingsFromConfig(const FluidConfig& config,
                                          const Eigen::AlignedBox3f& container,
                                          std::vector<std::string>* notes = nullptr);

// A user who sets camera_position_* or camera_look_at_* (start-up parameters or a
// reconfigure request, named in `set_by_user`) wants that camera: camera_auto is turned off
// unless camera_auto itself is among the names. Returns true when it turned it off.
bool applyCameraOverride(const std::set<std::string>& set_by_user, FluidConfig& config);

}  // namespace pbf_ros
