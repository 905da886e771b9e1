// fillParticleCloud: fields, layout, values, and that non-finite particles never get out.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <sensor_msgs/point_cloud2_iterator.h>

#include "pbf_ros/ros/CloudConversion.h"

using pbf_ros::fillParticleCloud;

TEST(CloudConversion, FieldsAreFloat32InDocumentedOrder) {
  sensor_msgs::PointCloud2 cloud;
  fillParticleCloud({Eigen::Vector3f(1, 2, 3)}, {Eigen::Vector3f(4, 5, 6)}, {998.0f}, {}, cloud);
  const char* names[] = {"x", "y", "z", "vx", "vy", "vz", "density", "speed", "id"};
  ASSERT_EQ(cloud.fields.size(), 9u);
  for (std::size_t i = 0; i < cloud.fields.size(); ++i) {
    EXPECT_EQ(cloud.fields[i].name, names[i]);
    EXPECT_EQ(cloud.fields[i].datatype,
              i < 8 ? sensor_msgs::PointField::FLOAT32 : sensor_msgs::PointField::UINT32);
    EXPECT_EQ(cloud.fields[i].count, 1u);
    EXPECT_EQ(cloud.fields[i].offset, 4 * i);
  }
  EXPECT_EQ(cloud.point_step, 36u);
}

TEST(CloudConversion, SizeAndValuesMatchTheParticles) {
  std::vector<Eigen::Vector3f> p, v;
  std::vector<float> rho;
  for (int i = 0; i < 100; ++i) {
    p.emplace_back(0.01f * i, 0.5f, -0.25f * i);
    v.emplace_back(3.0f, 0.0f, 4.0f);
    rho.push_back(1000.0f + i);
  }
  sensor_msgs::PointCloud2 cloud;
  EXPECT_EQ(fillParticleCloud(p, v, rho, {}, cloud), 0u);
  EXPECT_EQ(cloud.width * cloud.height, 100u);
  EXPECT_EQ(cloud.data.size(), 100u * cloud.point_step);
  EXPECT_EQ(cloud.row_step, cloud.width * cloud.point_step);
  EXPECT_TRUE(cloud.is_dense);

  sensor_msgs::PointCloud2ConstIterator<float> x(cloud, "x"), z(cloud, "z"), vz(cloud, "vz"),
      density(cloud, "density"), speed(cloud, "speed");
  for (int i = 0; i < 100; ++i, ++x, ++z, ++vz, ++density, ++speed) {
    EXPECT_FLOAT_EQ(*x, 0.01f * i);
    EXPECT_FLOAT_EQ(*z, -0.25f * i);
    EXPECT_FLOAT_EQ(*vz, 4.0f);
    EXPECT_FLOAT_EQ(*density, 1000.0f + i);
    EXPECT_FLOAT_EQ(*speed, 5.0f);
  }
}

TEST(CloudConversion, MissingDensitiesAndVelocitiesAreZero) {
  sensor_msgs::PointCloud2 cloud;
  fillParticleCloud({Eigen::Vector3f(1, 2, 3), Eigen::Vector3f(4, 5, 6)}, {}, {}, {}, cloud);
  ASSERT_EQ(cloud.width, 2u);
  sensor_msgs::PointCloud2ConstIterator<float> vx(cloud, "vx"), density(cloud, "density");
  EXPECT_EQ(*vx, 0.0f);
  EXPECT_EQ(*density, 0.0f);
}

TEST(CloudConversion, NonFiniteParticlesAreLeftOut) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  std::vector<Eigen::Vector3f> p = {Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(nan, 0, 0),
                                    Eigen::Vector3f(1, 1, 1), Eigen::Vector3f(2, 2, 2)};
  std::vector<Eigen::Vector3f> v = {Eigen::Vector3f::Zero(), Eigen::Vector3f::Zero(),
                                    Eigen::Vector3f(0, inf, 0), Eigen::Vector3f::Zero()};
  std::vector<float> rho = {1000.0f, 1000.0f, 1000.0f, nan};
  sensor_msgs::PointCloud2 cloud;
  EXPECT_EQ(fillParticleCloud(p, v, rho, {}, cloud), 3u);
  EXPECT_EQ(cloud.width, 1u);
  EXPECT_EQ(cloud.data.size(), cloud.point_step);
  for (std::size_t i = 0; i < cloud.data.size(); i += 4) {
    float f;
    std::memcpy(&f, &cloud.data[i], 4);
    EXPECT_TRUE(std::isfinite(f));
  }
}

TEST(CloudConversion, ReusedMessageShrinks) {
  sensor_msgs::PointCloud2 cloud;
  fillParticleCloud(std::vector<Eigen::Vector3f>(50, Eigen::Vector3f::Zero()), {}, {}, {}, cloud);
  fillParticleCloud(std::vector<Eigen::Vector3f>(3, Eigen::Vector3f::Zero()), {}, {}, {}, cloud);
  EXPECT_EQ(cloud.width, 3u);
  EXPECT_EQ(cloud.data.size(), 3u * cloud.point_step);
  EXPECT_EQ(cloud.fields.size(), 9u);
}

TEST(CloudConversion, IdsFollowTheirParticles) {
  sensor_msgs::PointCloud2 cloud;
  const std::vector<Eigen::Vector3f> p = {Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(1, 0, 0),
                                          Eigen::Vector3f(NAN, 0, 0), Eigen::Vector3f(3, 0, 0)};
  fillParticleCloud(p, {}, {}, {7u, 4000000000u, 9u, 12u}, cloud);
  ASSERT_EQ(cloud.width, 3u);  // the non-finite one (id 9) is left out, with its id
  sensor_msgs::PointCloud2ConstIterator<std::uint32_t> id(cloud, "id");
  sensor_msgs::PointCloud2ConstIterator<float> x(cloud, "x");
  const std::uint32_t expected_id[] = {7u, 4000000000u, 12u};
  const float expected_x[] = {0.0f, 1.0f, 3.0f};
  for (int i = 0; i < 3; ++i, ++id, ++x) {
    EXPECT_EQ(*id, expected_id[i]);
    EXPECT_EQ(*x, expected_x[i]);
  }
}
