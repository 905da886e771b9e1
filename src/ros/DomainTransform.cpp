#include "pbf_ros/ros/DomainTransform.h"

#include <tf2/LinearMath/Quaternion.h>

namespace pbf_ros {

geometry_msgs::TransformStamped makeDomainTransform(const pbf::Scene& scene,
                                                    const std::string& world_frame,
                                                    const std::string& domain_frame,
                                                    const ros::Time& stamp) {
  geometry_msgs::TransformStamped t;
  t.header.stamp = stamp;
  t.header.frame_id = world_frame;
  t.child_frame_id = domain_frame;
  t.transform.translation.x = scene.domain_translation.x();
  t.transform.translation.y = scene.domain_translation.y();
  t.transform.translation.z = scene.domain_translation.z();
  tf2::Quaternion q;
  q.setRPY(scene.domain_rpy.x(), scene.domain_rpy.y(), scene.domain_rpy.z());
  q.normalize();
  t.transform.rotation.x = q.x();
  t.transform.rotation.y = q.y();
  t.transform.rotation.z = q.z();
  t.transform.rotation.w = q.w();
  return t;
}

}  // namespace pbf_ros
