#include "NeighborSums.h"

#include <algorithm>
#include <cmath>

// x86-64-v3 is the AVX2 + FMA + BMI level every x86 CPU since ~2015 has; "default" is
// whatever the build targets (plain x86-64 for the portable build). Other compilers and
// architectures get the single build-target version.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define PBF_HOT_KERNEL __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define PBF_HOT_KERNEL
#endif

namespace pbf {

// Every loop below is branch-free over the neighbour list (masks instead of `if`), so the
// compiler vectorises it; the order of the additions is the compiler's, identical for every
// thread count (each particle's sum is computed by one thread).

PBF_HOT_KERNEL
LambdaSums lambdaSums(const NeighborArrays& a, const PairConstants& k, std::size_t i,
                      float* pair_gradient) {
  const float* P = a.position;
  const float xi = P[3 * i], yi = P[3 * i + 1], zi = P[3 * i + 2];
  float rho = 0.0f, gx = 0.0f, gy = 0.0f, gz = 0.0f, sum_grad2 = 0.0f;
  int coincident = 0;
#pragma omp simd reduction(+ : rho, gx, gy, gz, sum_grad2, coincident)
  for (std::uint32_t e = a.offset[i]; e < a.offset[i + 1]; ++e) {
    const std::uint32_t j = a.index[e];
    const float dx = xi - P[3 * j], dy = yi - P[3 * j + 1], dz = zi - P[3 * j + 2];
    const float r2 = dx * dx + dy * dy + dz * dz;
    const float w = std::max(k.h2 - r2, 0.0f);
    rho += k.poly6 * w * w * w;
    const float rlen = std::sqrt(r2);
    const float dl = std::max(k.h - rlen, 0.0f);
    const float g = r2 > k.coincident2 ? k.spiky * dl * dl / rlen : 0.0f;
    pair_gradient[e] = g;
    coincident += r2 <= k.coincident2 ? 1 : 0;
    gx += g * dx;
    gy += g * dy;
    gz += g * dz;
    sum_grad2 += g * g * r2;
  }
  return {rho, gx, gy, gz, sum_grad2, coincident};
}

PBF_HOT_KERNEL
VectorSum deltaSums(const NeighborArrays& a, float coincident2, std::size_t i, const float* lambda,
                    const float* pair_gradient) {
  const float* P = a.position;
  const float xi = P[3 * i], yi = P[3 * i + 1], zi = P[3 * i + 2];
  const float li = lambda[i];
  float sx = 0.0f, sy = 0.0f, sz = 0.0f;
  int coincident = 0;
#pragma omp simd reduction(+ : sx, sy, sz, coincident)
  for (std::uint32_t e = a.offset[i]; e < a.offset[i + 1]; ++e) {
    const std::uint32_t j = a.index[e];
    const float dx = xi - P[3 * j], dy = yi - P[3 * j + 1], dz = zi - P[3 * j + 2];
    const float g = (li + lambda[j]) * pair_gradient[e];
    coincident += dx * dx + dy * dy + dz * dz <= coincident2 ? 1 : 0;
    sx += g * dx;
    sy += g * dy;
    sz += g * dz;
  }
  return {sx, sy, sz, coincident};
}

PBF_HOT_KERNEL
DensitySum densitySums(const NeighborArrays& a, const PairConstants& k, std::size_t i) {
  const float* P = a.position;
  const float xi = P[3 * i], yi = P[3 * i + 1], zi = P[3 * i + 2];
  float rho = 0.0f;
  std::uint32_t count = 0;
#pragma omp simd reduction(+ : rho, count)
  for (std::uint32_t e = a.offset[i]; e < a.offset[i + 1]; ++e) {
    const std::uint32_t j = a.index[e];
    const float dx = xi - P[3 * j], dy = yi - P[3 * j + 1], dz = zi - P[3 * j + 2];
    const float r2 = dx * dx + dy * dy + dz * dz;
    const float w = std::max(k.h2 - r2, 0.0f);
    rho += k.poly6 * w * w * w;
    count += r2 < k.h2 ? 1u : 0u;
  }
  return {rho, count};
}

PBF_HOT_KERNEL
VectorSum xsphSums(const NeighborArrays& a, const PairConstants& k, std::size_t i,
                   const float* velocity, const float* density) {
  const float* P = a.position;
  const float* V = velocity;
  const float xi = P[3 * i], yi = P[3 * i + 1], zi = P[3 * i + 2];
  const float ux = V[3 * i], uy = V[3 * i + 1], uz = V[3 * i + 2];
  float sx = 0.0f, sy = 0.0f, sz = 0.0f;
#pragma omp simd reduction(+ : sx, sy, sz)
  for (std::uint32_t e = a.offset[i]; e < a.offset[i + 1]; ++e) {
    const std::uint32_t j = a.index[e];
    const float dx = xi - P[3 * j], dy = yi - P[3 * j + 1], dz = zi - P[3 * j + 2];
    const float w = std::max(k.h2 - (dx * dx + dy * dy + dz * dz), 0.0f);
    const float f = k.poly6 * w * w * w / density[j];  // V_j W_ij
    sx += f * (V[3 * j] - ux);
    sy += f * (V[3 * j + 1] - uy);
    sz += f * (V[3 * j + 2] - uz);
  }
  return {sx, sy, sz, 0};
}

}  // namespace pbf
