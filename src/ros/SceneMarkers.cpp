#include "pbf_ros/ros/ContainerMarkers.h"

#include <geometry_msgs/Point.h>

namespace pbf_ros {

namespace {
geometry_msgs::Point point(float x, float y, float z) {
  geometry_msgs::Point p;
  p.x = x;
  p.y = y;
  p.z = z;
  return p;
}
}  // namespace

visualization_msgs::MarkerArray makeContainerMarkers(const Eigen::AlignedBox3f& box,
                                                     const std::string& frame_id,
                                                     const ros::Time& stamp) {
  visualization_msgs::MarkerArray array;

  visualization_msgs::Marker clear;
  clear.header.frame_id = frame_id;
  clear.header.stamp = stamp;
  clear.action = visualization_msgs::Marker::DELETEALL;
  array.markers.push_back(clear);

  // Wireframe: the 12 edges of the box.
  visualization_msgs::Marker edges;
  edges.header.frame_id = frame_id;
  edges.header.stamp = stamp;
  edges.ns = "container";
  edges.id = 0;
  edges.type = visualization_msgs::Marker::LINE_LIST;
  edges.action = visualization_msgs::Marker::ADD;
  edges.pose.orientation.w = 1.0;
  edges.scale.x = 0.005 * std::max(1.0f, box.sizes().maxCoeff());  // line width [m]
  edges.color.r = 0.85f;
  edges.color.g = 0.85f;
  edges.color.b = 0.9f;
  edges.color.a = 1.0f;
  const Eigen::Vector3f lo = box.min(), hi = box.max();
  const float xs[2] = {lo.x(), hi.x()}, ys[2] = {lo.y(), hi.y()}, zs[2] = {lo.z(), hi.z()};
  for (int a = 0; a < 2; ++a) {
    for (int b = 0; b < 2; ++b) {
      edges.points.push_back(point(xs[0], ys[a], zs[b]));  // along x
      edges.points.push_back(point(xs[1], ys[a], zs[b]));
      edges.points.push_back(point(xs[a], ys[0], zs[b]));  // along y
      edges.points.push_back(point(xs[a], ys[1], zs[b]));
      edges.points.push_back(point(xs[a], ys[b], zs[0]));  // along z
      edges.points.push_back(point(xs[a], ys[b], zs[1]));
    }
  }
  array.markers.push_back(edges);

  // A faint floor so the eye finds "down".
  visualization_msgs::Marker floor;
  floor.header = edges.header;
  floor.ns = "container";
  floor.id = 1;
  floor.type = visualization_msgs::Marker::CUBE;
  floor.action = visualization_msgs::Marker::ADD;
  const Eigen::Vector3f c = box.center();
  const float thickness = 0.002f * std::max(1.0f, box.sizes().maxCoeff());
  floor.pose.position = point(c.x(), c.y(), lo.z() - 0.5f * thickness);
  floor.pose.orientation.w = 1.0;
  floor.scale.x = box.sizes().x();
  floor.scale.y = box.sizes().y();
  floor.scale.z = thickness;
  floor.color.r = 0.5f;
  floor.color.g = 0.5f;
  floor.color.b = 0.55f;
  floor.color.a = 0.6f;
  array.markers.push_back(floor);
  return array;
}

}  // namespace pbf_ros
