#pragma once
// Measurements on a particle state, shared by tests, pbf_bench and pbf_stress.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace pbf {

// Height of the free surface above the container floor, a level gauge: particles are binned
// into vertical columns four spacings wide; in each, the colour field (every particle's
// calibrated volume spread over the column by the kernel, Spiky with h = 2 d) is followed
// down from above to where it reaches one half, less the 0.146 d by which the discrete
// layers of a resting lattice put that point below the lattice's surface (its top layer
// plus half a spacing): the start lattice reads its own level. Returns the median over the
// columns not touching a side wall (all columns where there are at most two per axis). A
// rough or sunken top layer reads as its volume sits; a splashing particle does not count.
// 0 when there is nothing to read: no particles, no spacing, an empty container.
double freeSurfaceHeight(const std::vector<Eigen::Vector3f>& positions, float spacing,
                         const Eigen::AlignedBox3f& container);

// The particles' mean height above the container floor [m]. Twice it is the level of a
// uniform column with the water's potential energy: its drop is the fluid's compaction,
// however the surface's layers sit (doc/calibration.md, the start-up and the level).
double meanHeightAboveFloor(const std::vector<Eigen::Vector3f>& positions, const Eigen::AlignedBox3f& container);

// Number of particles farther than `tolerance` outside the box.
std::size_t countOutside(const std::vector<Eigen::Vector3f>& positions,
                         const Eigen::AlignedBox3f& box, float tolerance);

// True when every component of every vector is finite.
bool allFinite(const std::vector<Eigen::Vector3f>& values);

// Total momentum sum m v (equal masses): returns sum v; multiply by the mass.
Eigen::Vector3d velocitySum(const std::vector<Eigen::Vector3f>& velocities);

}  // namespace pbf
