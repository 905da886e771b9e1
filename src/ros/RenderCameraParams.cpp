#include "pbf_ros/ros/RenderCameraParams.h"

#include <algorithm>
#include <cmath>

namespace pbf_ros {

namespace {
constexpr float kAutoAzimuth = -60.0f * static_cast<float>(M_PI) / 180.0f;
constexpr float kAutoElevation = 30.0f * static_cast<float>(M_PI) / 180.0f;
constexpr float kAutoMargin = 1.05f;

Eigen::Vector3f corner(const Eigen::AlignedBox3f& box, int i) {
  return Eigen::Vector3f((i & 1) ? box.max().x() : box.min().x(),
                         (i & 2) ? box.max().y() : box.min().y(),
                         (i & 4) ? box.max().z() : box.min().z());
}
}  // namespace

Eigen::Isometry3f frameContainer(const Eigen::AlignedBox3f& container, float vertical_fov,
                                 int width, int height) {
  const Eigen::Vector3f target = container.center();
  // Unit vector from the target towards the eye.
  const Eigen::Vector3f back(std::cos(kAutoElevation) * std::cos(kAutoAzimuth),
                             std::cos(kAutoElevation) * std::sin(kAutoAzimuth),
                             std::sin(kAutoElevation));
  // The orientation does not depend on the distance: find it at unit distance.
  const Eigen::Matrix3f r = pbf::lookAt(target + back, target).linear();
  const float tan_v = std::tan(0.5f * vertical_fov);
  const float tan_h = tan_v * static_cast<float>(width) / static_cast<float>(height);
  // Corner p (relative to the target) at eye distance D: x = p.right, y = p.down,
  // depth = D - p.back. It is inside the image when |x| <= tan_h * depth and |y| <= tan_v * depth.
  float distance = 0.0f;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3f p = corner(container, i) - target;
    const float along = p.dot(back);
    distance = std::max(distance, along + kAutoMargin * std::abs(p.dot(r.col(0))) / tan_h);
    distance = std::max(distance, along + kAutoMargin * std::abs(p.dot(r.col(1))) / tan_v);
  }
  distance = std::max(distance, 0.1f);
  return pbf::lookAt(target + distance * back, target);
}

pbf::RenderCamera renderCameraFromConfig(const FluidConfig& config,
                                         const Eigen::AlignedBox3f& container) {
  pbf::RenderCamera camera;
  camera.width = config.render_width;
  camera.height = config.render_height;
  camera.vertical_fov = static_cast<float>(config.render_vfov);
  if (config.camera_auto) {
    camera.camera_to_world =
        frameContainer(container, camera.vertical_fov, camera.width, camera.height);
  } else {
    const Eigen::Vector3f eye(static_cast<float>(config.camera_position_x),
                              static_cast<float>(config.camera_position_y),
                              static_cast<float>(config.camera_position_z));
    Eigen::Vector3f target(static_cast<float>(config.camera_look_at_x),
                           static_cast<float>(config.camera_look_at_y),
                           static_cast<float>(config.camera_look_at_z));
    if ((target - eye).norm() < 1e-6f) target = eye + Eigen::Vector3f::UnitX();  // degenerate
    camera.camera_to_world = pbf::lookAt(eye, target);
  }
  // Clip planes around the container (the scene of interest), never tighter than the
  // defaults where that would cut it.
  const Eigen::Vector3f eye = camera.camera_to_world.translation();
  const float farthest = (container.center() - eye).norm() + 0.5f * container.diagonal().norm();
  camera.far_clip = std::max(camera.far_clip, 2.0f * farthest);
  return camera;
}

bool knownRenderFilter(const std::string& name) {
  return name == "narrow_range" || name == "bilateral" || name == "none";
}

pbf::RenderOptions renderOptionsFromConfig(const FluidConfig& config,
                                           const Eigen::AlignedBox3f& container,
                                           std::vector<std::string>* notes) {
  pbf::RenderOptions o;
  if (config.render_filter == "narrow_range") {
    o.filter = pbf::DepthFilter::NarrowRange;
  } else if (config.render_filter == "bilateral") {
    o.filter = pbf::DepthFilter::Bilateral;
  } else if (config.render_filter == "none") {
    o.filter = pbf::DepthFilter::None;
  } else {
    o.filter = pbf::DepthFilter::NarrowRange;
    if (notes) {
      notes->push_back("render_filter: '" + config.render_filter +
                       "' is not narrow_range, bilateral or none; using narrow_range");
    }
  }
  o.filter_sigma_in_radii = static_cast<float>(config.render_filter_sigma);
  o.max_filter_radius_pixels = config.render_filter_max_radius;
  o.gap_closing_in_radii = static_cast<float>(config.render_gap_closing);
  o.narrow_range_threshold_in_radii = static_cast<float>(config.render_narrow_range_threshold);
  o.narrow_range_clamp_in_radii = static_cast<float>(config.render_narrow_range_clamp);
  o.bilateral_depth_sigma_in_radii = static_cast<float>(config.render_bilateral_depth_sigma);
  o.surface_particles_only = config.render_surface_only;
  o.draw_background = config.render_background;
  o.floor_height = container.min().z();
  return o;
}

SurfaceSettings surfaceSettingsFromConfig(const FluidConfig& config,
                                          const Eigen::AlignedBox3f& container,
                                          std::vector<std::string>* notes) {
  SurfaceSettings s;
  s.camera = renderCameraFromConfig(config, container);
  s.options = renderOptionsFromConfig(config, container, notes);
  s.rate = config.render_rate;
  return s;
}

bool applyCameraOverride(const std::set<std::string>& set_by_user, FluidConfig& config) {
  if (!config.camera_auto || set_by_user.count("camera_auto")) return false;
  static const char* const kNames[] = {"camera_position_x", "camera_position_y",
                                       "camera_position_z", "camera_look_at_x",
                                       "camera_look_at_y",  "camera_look_at_z"};
  for (const char* name : kNames) {
    if (set_by_user.count(name)) {
      config.camera_auto = false;
      return true;
    }
  }
  return false;
}

}  // namespace pbf_ros
