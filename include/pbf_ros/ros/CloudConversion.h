#pragma once
// Solver arrays -> sensor_msgs/PointCloud2. A plain function (no node, no master) so it is
// unit-tested on its own and reused by anyone who has particle arrays.

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <sensor_msgs/PointCloud2.h>
#include <vector>

namespace pbf_ros {

// Number of float32 fields per point: x y z vx vy vz density speed; then the uint32 id.
constexpr std::size_t kCloudFieldCount = 8;

// Fills `cloud` (fields, layout and data; the header is the caller's) with one point per
// particle: x y z [m], vx vy vz [m/s], density [kg/m^3], speed [m/s], all float32, then `id`
// (uint32), height 1, dense. speed = |v| is redundant but lets rviz (which colours by one
// channel) show it. The id is the solver's particle id: stable while the particle exists
// (the cloud's order changes every step), never given twice until a reset; consumers
// follow particles by it. `densities` may be empty (before the first step): density is 0
// then; `ids` may be empty: the point's index then.
// Particles with a non-finite value are left out so NaN never reaches the wire (the solver
// never produces them; this is a last guard). Returns how many were left out.
std::size_t fillParticleCloud(const std::vector<Eigen::Vector3f>& positions,
                              const std::vector<Eigen::Vector3f>& velocities,
                              const std::vector<float>& densities,
                              const std::vector<std::uint32_t>& ids,
                              sensor_msgs::PointCloud2& cloud);

}  // namespace pbf_ros
