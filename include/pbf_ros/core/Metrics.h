#pragma once
// Measurements on a particle state, shared by tests, pbf_bench and pbf_stress.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace pbf {

// Height of the free surface above the container floor: particles are binned into
// vertical columns of width 2 * spacing; each column's top is its highest particle plus
// half a spacing (the particle radius); the median over columns not touching a side wall
// is returned. Robust to a few splashing particles.
double freeSurfaceHeight(const std::vector<Eigen::Vector3f>& positions, float spacing,
                         const Eigen::AlignedBox3f& container);

// Number of particles farther than `tolerance` outside the box.
std::size_t countOutside(const std::vector<Eigen::Vector3f>& positions,
                         const Eigen::AlignedBox3f& box, float tolerance);

// True when every component of every vector is finite.
bool allFinite(const std::vector<Eigen::Vector3f>& values);

// Total momentum sum m v (equal masses): returns sum v; multiply by the mass.
Eigen::Vector3d velocitySum(const std::vector<Eigen::Vector3f>& velocities);

}  // namespace pbf
