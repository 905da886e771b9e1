#pragma once
// Per-particle vectors copied into 16-byte slots (x, y, z, w) for the x86-64-v3 neighbour
// sums (NeighborArrays::packed, xsphSums' velocity_slots): eight neighbours then come in
// with eight 128-bit loads and a transpose instead of three or more gathers (the lambda sums
// of a 20k lattice took a third less time on an AMD family 26 CPU). Private to pbf_core.
//
// Two sets of slots, so that no pass writes what another thread of it reads:
// - the constraint iteration: the lambda pass reads the positions (set 1, w = 0) and writes
//   each particle's (x, y, z, lambda) into set 2, which the delta-p pass reads;
// - the velocity passes: positions in set 1, velocities with the density in w in set 2.

#include <Eigen/Core>
#include <Eigen/StdVector>

#include <cstddef>
#include <vector>

#include "NeighborSums.h"

namespace pbf {

class PackedSlots {
 public:
  // Each call below returns nullptr, and copies nothing, when the running kernels do not
  // read slots. The copies run their own parallel loop: call them between passes.

  // Copies the positions into set 1 (w = 0) and sizes set 2 alike; returns set 1.
  const float* packPositions(const std::vector<Eigen::Vector3f>& positions) {
    if (!neighborSumsReadPacked()) return nullptr;
    const std::size_t n = positions.size();
    positions_.resize(n);
    second_.resize(n);
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) positions_[i] << positions[i], 0.0f;
    return data(positions_);
  }

  // The Gauss-Seidel sweep's working positions: copied into set 1 (w = 0), which the sweep
  // then moves in place (and copies back itself).
  float* sweepPositions(const std::vector<Eigen::Vector3f>& positions) {
    return packPositions(positions) == nullptr ? nullptr : data(positions_);
  }

  // Set 2, for the lambda pass to fill with (x, y, z, lambda).
  float* lambdaSlots() { return neighborSumsReadPacked() ? data(second_) : nullptr; }

  // Copies velocities and densities into set 2; returns it.
  const float* packVelocities(const std::vector<Eigen::Vector3f>& velocity,
                              const std::vector<float>& density) {
    if (!neighborSumsReadPacked()) return nullptr;
    const std::size_t n = velocity.size();
    second_.resize(n);
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) second_[i] << velocity[i], density[i];
    return data(second_);
  }

 private:
  using Slots = std::vector<Eigen::Vector4f, Eigen::aligned_allocator<Eigen::Vector4f>>;
  static float* data(Slots& s) { return s.empty() ? nullptr : s[0].data(); }
  Slots positions_, second_;
};

}  // namespace pbf
