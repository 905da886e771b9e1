#pragma once
// Free-surface measurements for the dam break, robust to splash: a few droplets ahead of
// the surge must not count as "the front".

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace pbf_bench {

// Surge-front position along +x, measured from the container's back wall (x min).
// Particles are binned along x in slabs one spacing thick. A slab belongs to the fluid
// body when it holds at least `min_fraction` of a full particle row across the tank
// (min_fraction * width_y / spacing particles); the front is the far edge of the last such
// slab reached from the back wall without a gap wider than one slab. Isolated droplets
// ahead of the surge (a handful of particles) are thereby ignored.
double surgeFront(const std::vector<Eigen::Vector3f>& positions, float spacing,
                  const Eigen::AlignedBox3f& container, double min_fraction = 0.5);

// The same front without the slabs' quantisation (the slab front moves in steps of one
// spacing, 0.1 a at a/d = 10, which is what the resolution and dt comparisons would
// otherwise measure): a window one spacing thick slides along x from particle to particle
// instead of standing on a fixed grid. The front is the far end of the last window that
// holds `min_fraction` of a row, reached from the back wall without a gap wider than one
// spacing between such windows, plus half a spacing (the particle's own extent). For a
// lattice face it equals the slab front; as the surge tip thins it moves with the particles.
double surgeFrontSliding(const std::vector<Eigen::Vector3f>& positions, float spacing,
                         const Eigen::AlignedBox3f& container, double min_fraction = 0.5);

// Height of the fluid above the floor in slabs along x of width `bin` (0 where a slab is
// empty): the mean over y-columns (width 2 spacing) of each column's top particle plus
// half a spacing. Used to compare the shape of two runs of the same scene.
std::vector<double> heightProfile(const std::vector<Eigen::Vector3f>& positions, float spacing,
                                  const Eigen::AlignedBox3f& container, double bin);

}  // namespace pbf_bench
