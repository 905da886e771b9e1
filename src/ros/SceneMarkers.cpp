#include "pbf_ros/ros/SceneMarkers.h"

#include <algorithm>
#include <geometry_msgs/Point.h>

namespace pbf_ros {

namespace {
geometry_msgs::Point point(const Eigen::Vector3f& v) {
  geometry_msgs::Point p;
  p.x = v.x();
  p.y = v.y();
  p.z = v.z();
  return p;
}


visualization_msgs::Marker marker(const std::string& frame, const ros::Time& stamp,
                                  const std::string& ns, int id, int type) {
  visualization_msgs::Marker m;
  m.header.frame_id = frame;
  m.header.stamp = stamp;
  m.ns = ns;
  m.id = id;
  m.type = type;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  // Re-transformed every frame with the latest tf: solids attached to moving frames move.
  m.frame_locked = true;
  return m;
}

void setColor(visualization_msgs::Marker& m, float r, float g, float b, float a) {
  m.color.r = r;
  m.color.g = g;
  m.color.b = b;
  m.color.a = a;
}

void addContainer(const Eigen::AlignedBox3f& box, const std::string& frame,
                  const ros::Time& stamp, visualization_msgs::MarkerArray& array) {
  // Wireframe: the 12 edges of the box.
  auto edges = marker(frame, stamp, "container", 0, visualization_msgs::Marker::LINE_LIST);
  edges.scale.x = 0.005 * std::max(1.0f, box.sizes().maxCoeff());  // line width [m]
  setColor(edges, 0.85f, 0.85f, 0.9f, 1.0f);
  const Eigen::Vector3f lo = box.min(), hi = box.max();
  const float xs[2] = {lo.x(), hi.x()}, ys[2] = {lo.y(), hi.y()}, zs[2] = {lo.z(), hi.z()};
  for (int a = 0; a < 2; ++a) {
    for (int b = 0; b < 2; ++b) {
      edges.points.push_back(point({xs[0], ys[a], zs[b]}));  // along x
      edges.points.push_back(point({xs[1], ys[a], zs[b]}));
      edges.points.push_back(point({xs[a], ys[0], zs[b]}));  // along y
      edges.points.push_back(point({xs[a], ys[1], zs[b]}));
      edges.points.push_back(point({xs[a], ys[b], zs[0]}));  // along z
      edges.points.push_back(point({xs[a], ys[b], zs[1]}));
    }
  }
  array.markers.push_back(edges);

  // A faint floor so the eye finds "down".
  auto floor = marker(frame, stamp, "container", 1, visualization_msgs::Marker::CUBE);
  const float thickness = 0.002f * std::max(1.0f, box.sizes().maxCoeff());
  const Eigen::Vector3f c = box.center();
  floor.pose.position = point({c.x(), c.y(), lo.z() - 0.5f * thickness});
  floor.scale.x = box.sizes().x();
  floor.scale.y = box.sizes().y();
  floor.scale.z = thickness;
  setColor(floor, 0.5f, 0.5f, 0.55f, 0.6f);
  array.markers.push_back(floor);
}

void addObstacle(const pbf::Obstacle& o, const std::string& domain_frame, const ros::Time& stamp,
                 int& id, visualization_msgs::MarkerArray& array) {
  // Attached obstacles are drawn in their frame at their offset; static ones at their pose.
  const std::string frame = o.frame.empty() ? domain_frame : o.frame;
  const Eigen::Isometry3f pose = o.frame.empty() ? o.pose : o.offset;
  auto solid = [&](int type) {
    auto m = marker(frame, stamp, "obstacles", id++, type);
    m.pose = poseMsg(pose);
    setColor(m, 0.95f, 0.6f, 0.2f, 0.8f);
    return m;
  };
  switch (o.shape) {
    case pbf::Obstacle::Shape::Box: {
      auto m = solid(visualization_msgs::Marker::CUBE);
      m.scale.x = 2.0 * o.half_extents.x();
      m.scale.y = 2.0 * o.half_extents.y();
      m.scale.z = 2.0 * o.half_extents.z();
      array.markers.push_back(m);
      break;
    }
    case pbf::Obstacle::Shape::Sphere: {
      auto m = solid(visualization_msgs::Marker::SPHERE);
      m.scale.x = m.scale.y = m.scale.z = 2.0 * o.radius;
      array.markers.push_back(m);
      break;
    }
    case pbf::Obstacle::Shape::Capsule: {
      // A cylinder along local z plus a sphere on each end.
      auto body = solid(visualization_msgs::Marker::CYLINDER);
      body.scale.x = body.scale.y = 2.0 * o.radius;
      body.scale.z = 2.0 * o.half_length;
      array.markers.push_back(body);
      for (float end : {-o.half_length, o.half_length}) {
        auto cap = solid(visualization_msgs::Marker::SPHERE);
        cap.pose = poseMsg(pose * Eigen::Translation3f(0.0f, 0.0f, end));
        cap.scale.x = cap.scale.y = cap.scale.z = 2.0 * o.radius;
        array.markers.push_back(cap);
      }
      break;
    }
    case pbf::Obstacle::Shape::Cylinder: {
      auto m = solid(visualization_msgs::Marker::CYLINDER);  // rviz's cylinder is along z too
      m.scale.x = m.scale.y = 2.0 * o.radius;
      m.scale.z = 2.0 * o.half_length;
      array.markers.push_back(m);
      break;
    }
    case pbf::Obstacle::Shape::Mesh: {
      // The triangles the grid was built from, so the marker shows what the fluid meets.
      auto m = solid(visualization_msgs::Marker::TRIANGLE_LIST);
      m.scale.x = m.scale.y = m.scale.z = 1.0;
      if (o.sdf) {
        const pbf::TriangleMesh& mesh = o.sdf->mesh();
        m.points.reserve(3 * mesh.triangles.size());
        for (const Eigen::Vector3i& t : mesh.triangles)
          for (int k = 0; k < 3; ++k) m.points.push_back(point(mesh.vertices[t[k]]));
      }
      array.markers.push_back(m);
      break;
    }
  }
}
// A nozzle: an arrow along the jet (as long as three radii, at least 5 cm) from the centre
// of its opening, drawn in its frame so that it moves with it.
void addEmitter(const pbf::Emitter& e, const std::string& domain_frame, const ros::Time& stamp, int id,
                visualization_msgs::MarkerArray& array) {
  auto m = marker(e.frame.empty() ? domain_frame : e.frame, stamp, "emitters", id,
                  visualization_msgs::Marker::ARROW);
  const float length = std::max(0.05f, 3.0f * e.radius);
  const Eigen::Vector3f dir = e.direction.normalized();
  m.points.push_back(point(e.position - length * dir));
  m.points.push_back(point(e.position));
  m.scale.x = 0.5 * e.radius;  // shaft diameter
  m.scale.y = 2.0 * e.radius;  // head diameter: the nozzle's opening
  m.scale.z = 0.5 * length;    // head length
  setColor(m, 0.2f, 0.5f, 1.0f, 0.9f);
  array.markers.push_back(m);
}

// A drain: its region, translucent dark blue, in fluid_domain.
void addDrain(const pbf::Drain& d, const std::string& domain_frame, const ros::Time& stamp, int id,
              visualization_msgs::MarkerArray& array) {
  const bool box = d.shape == pbf::Drain::Shape::Box;
  auto m = marker(domain_frame, stamp, "drains", id,
                  box ? visualization_msgs::Marker::CUBE : visualization_msgs::Marker::SPHERE);
  const Eigen::Vector3f centre = box ? Eigen::Vector3f(0.5f * (d.min + d.max)) : d.center;
  const Eigen::Vector3f size = box ? Eigen::Vector3f(d.max - d.min) : Eigen::Vector3f::Constant(2.0f * d.radius);
  m.pose.position = point(centre);
  m.scale.x = size.x();
  m.scale.y = size.y();
  m.scale.z = size.z();
  setColor(m, 0.05f, 0.1f, 0.4f, 0.5f);
  array.markers.push_back(m);
}
}  // namespace

geometry_msgs::Pose poseMsg(const Eigen::Isometry3f& t) {
  geometry_msgs::Pose pose;
  pose.position = point(t.translation());
  const Eigen::Quaternionf q(t.linear());
  pose.orientation.x = q.x();
  pose.orientation.y = q.y();
  pose.orientation.z = q.z();
  pose.orientation.w = q.w();
  return pose;
}

visualization_msgs::MarkerArray makeSceneMarkers(const pbf::Scene& scene,
                                                 const std::string& domain_frame,
                                                 const ros::Time& stamp) {
  visualization_msgs::MarkerArray array;
  visualization_msgs::Marker clear;
  clear.header.frame_id = domain_frame;
  clear.header.stamp = stamp;
  clear.action = visualization_msgs::Marker::DELETEALL;
  array.markers.push_back(clear);

  // An attached container is given in fluid_domain coordinates at rest (its frame at
  // identity), so the same box drawn in its frame moves with it.
  addContainer(scene.container,
               scene.container_frame.empty() ? domain_frame : scene.container_frame, stamp,
               array);
  int id = 0;
  for (const pbf::Obstacle& o : scene.obstacles) addObstacle(o, domain_frame, stamp, id, array);
  for (std::size_t k = 0; k < scene.emitters.size(); ++k)
    addEmitter(scene.emitters[k], domain_frame, stamp, static_cast<int>(k), array);
  for (std::size_t k = 0; k < scene.drains.size(); ++k)
    addDrain(scene.drains[k], domain_frame, stamp, static_cast<int>(k), array);
  return array;
}

}  // namespace pbf_ros
