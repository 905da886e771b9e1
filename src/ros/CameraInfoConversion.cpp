#include "pbf_ros/ros/CameraInfoConversion.h"

#include <Eigen/Geometry>

namespace pbf_ros {

sensor_msgs::CameraInfo toCameraInfo(const pbf::RenderCamera& camera,
                                     const std_msgs::Header& header) {
  const pbf::PinholeIntrinsics k = pbf::intrinsicsOf(camera);
  sensor_msgs::CameraInfo info;
  info.header = header;
  info.width = static_cast<std::uint32_t>(camera.width);
  info.height = static_cast<std::uint32_t>(camera.height);
  info.distortion_model = "plumb_bob";
  info.D.assign(5, 0.0);
  info.K = {k.fx, 0.0, k.cx, 0.0, k.fy, k.cy, 0.0, 0.0, 1.0};
  info.R = {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0};
  info.P = {k.fx, 0.0, k.cx, 0.0, 0.0, k.fy, k.cy, 0.0, 0.0, 0.0, 1.0, 0.0};
  info.binning_x = 0;
  info.binning_y = 0;
  // roi all zeros = the full image
  return info;
}

geometry_msgs::TransformStamped toCameraTransform(const pbf::RenderCamera& camera,
                                                  const std::string& parent_frame,
                                                  const std::string& camera_frame,
                                                  const ros::Time& stamp) {
  geometry_msgs::TransformStamped t;
  t.header.stamp = stamp;
  t.header.frame_id = parent_frame;
  t.child_frame_id = camera_frame;
  const Eigen::Vector3f p = camera.camera_to_world.translation();
  const Eigen::Quaternionf q(camera.camera_to_world.linear());
  const Eigen::Quaternionf qn = q.normalized();
  t.transform.translation.x = p.x();
  t.transform.translation.y = p.y();
  t.transform.translation.z = p.z();
  t.transform.rotation.x = qn.x();
  t.transform.rotation.y = qn.y();
  t.transform.rotation.z = qn.z();
  t.transform.rotation.w = qn.w();
  return t;
}

}  // namespace pbf_ros
