#include "pbf_ros/ros/CloudConversion.h"

#include <cmath>
#include <cstring>
#include <sensor_msgs/point_cloud2_iterator.h>

namespace pbf_ros {

namespace {
bool finite3(const Eigen::Vector3f& v) {
  return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z());
}
}  // namespace

std::size_t fillParticleCloud(const std::vector<Eigen::Vector3f>& positions,
                              const std::vector<Eigen::Vector3f>& velocities,
                              const std::vector<float>& densities,
                              const std::vector<std::uint32_t>& ids,
                              sensor_msgs::PointCloud2& cloud) {
  const std::size_t n = positions.size();
  const bool have_velocities = velocities.size() == n;
  const bool have_densities = densities.size() == n;
  const bool have_ids = ids.size() == n;

  sensor_msgs::PointCloud2Modifier modifier(cloud);
  modifier.setPointCloud2Fields(
      kCloudFieldCount + 1, "x", 1, sensor_msgs::PointField::FLOAT32, "y", 1,
      sensor_msgs::PointField::FLOAT32, "z", 1, sensor_msgs::PointField::FLOAT32, "vx", 1,
      sensor_msgs::PointField::FLOAT32, "vy", 1, sensor_msgs::PointField::FLOAT32, "vz", 1,
      sensor_msgs::PointField::FLOAT32, "density", 1, sensor_msgs::PointField::FLOAT32, "speed",
      1, sensor_msgs::PointField::FLOAT32, "id", 1, sensor_msgs::PointField::UINT32);
  cloud.is_bigendian = false;  // x86 and ARM hosts are little endian; memcpy keeps host order
  cloud.data.resize(n * cloud.point_step);

  // Raw copies: the iterator interface costs several times more for large clouds.
  std::uint8_t* out = cloud.data.data();
  std::size_t written = 0;
  for (std::size_t i = 0; i < n; ++i) {
    float point[kCloudFieldCount];
    const Eigen::Vector3f v = have_velocities ? velocities[i] : Eigen::Vector3f::Zero();
    point[0] = positions[i].x();
    point[1] = positions[i].y();
    point[2] = positions[i].z();
    point[3] = v.x();
    point[4] = v.y();
    point[5] = v.z();
    point[6] = have_densities ? densities[i] : 0.0f;
    point[7] = v.norm();
    if (!finite3(positions[i]) || !finite3(v) || !std::isfinite(point[6]) ||
        !std::isfinite(point[7]))
      continue;
    const std::uint32_t id = have_ids ? ids[i] : static_cast<std::uint32_t>(i);
    std::memcpy(out + written * cloud.point_step, point, sizeof(point));
    std::memcpy(out + written * cloud.point_step + sizeof(point), &id, sizeof(id));
    ++written;
  }
  cloud.data.resize(written * cloud.point_step);
  cloud.height = 1;
  cloud.width = static_cast<std::uint32_t>(written);
  cloud.row_step = cloud.width * cloud.point_step;
  cloud.is_dense = true;
  return n - written;
}

}  // namespace pbf_ros
