#pragma once
// Pair geometry shared by the solver's neighbour passes (internal to pbf_core).

#include <Eigen/Core>
#include <algorithm>
#include <cstdint>

#include "pbf_ros/core/Kernels.h"

namespace pbf {

// Direction for a pair of coincident particles, which has no geometric direction: a
// pseudo-random unit vector from the pair's ids, antisymmetric (dir(a,b) = -dir(b,a)) so
// momentum is still conserved and coincident particles push apart deterministically.
inline Eigen::Vector3f coincidentDirection(std::uint32_t id_i, std::uint32_t id_j) {
  const std::uint32_t lo = std::min(id_i, id_j), hi = std::max(id_i, id_j);
  std::uint64_t s = (static_cast<std::uint64_t>(lo) << 32 | hi) * 0x9E3779B97F4A7C15ULL;
  auto next = [&s]() {
    s ^= s >> 31;
    s *= 0xBF58476D1CE4E5B9ULL;
    s ^= s >> 29;
    return static_cast<float>(s >> 40) / static_cast<float>(1 << 24) * 2.0f - 1.0f;
  };
  Eigen::Vector3f d(next(), next(), next());
  if (d.squaredNorm() < 1e-6f) d = Eigen::Vector3f(1, 0, 0);
  d.normalize();
  return id_i < id_j ? d : Eigen::Vector3f(-d);
}

// Pair geometry shared by every pass: r = p_i - p_j, its length, and the Spiky gradient
// grad_i W(r). Coincident pairs get the kernel's finite limit along coincidentDirection.
struct Pair {
  Eigen::Vector3f r;
  float r2;
  float rlen;
};

constexpr float kCoincident = 1e-12f;

inline Eigen::Vector3f spikyGradientSafe(const Kernels& k, const Pair& p, std::uint32_t id_i,
                                         std::uint32_t id_j) {
  if (p.r2 > kCoincident * k.h2) return k.spikyGradient(p.r, p.rlen);
  return (k.spiky_grad_coef * k.h2) * coincidentDirection(id_i, id_j);
}

}  // namespace pbf
