// The kernels proper. This file is compiled twice (cmake/core.cmake): once for the build's
// target into namespace pbf::neighbor_sums_base, once with -march=x86-64-v3 (AVX2 + FMA)
// into pbf::neighbor_sums_v3; NeighborSumsDispatch.cpp picks one at start-up. Only
// built-ins and fully inlined std functions may be used here: an out-of-line inline function
// emitted by the AVX2 copy could be picked by the linker for everyone else.
#include "NeighborSums.h"

#include <algorithm>
#include <cmath>

#ifndef PBF_NEIGHBOR_SUMS_NS
#error "compile NeighborSums.cpp with PBF_NEIGHBOR_SUMS_NS set (see cmake/core.cmake)"
#endif

namespace pbf {
namespace PBF_NEIGHBOR_SUMS_NS {

// Every loop below is branch-free over the neighbour list (masks instead of `if`), so the
// compiler vectorises it; the order of the additions is the compiler's, identical for every
// thread count (each particle's sum is computed by one thread). Two details GCC needs (check
// with -fopt-info-vec): a size_t loop index (with a 32-bit one, the store to pair_gradient
// stops vectorisation: the wrapping index makes the addresses non-affine), and
// -fno-trapping-math for this file (cmake/core.cmake) so that the division behind the
// coincident-pair mask may run in every lane; NaN and Inf still propagate.

LambdaSums lambdaSums(const NeighborArrays& a, const PairConstants& k, std::size_t i,
                      float* pair_gradient) {
  const float* P = a.position;
  const std::uint32_t* nbr = a.index;
  const std::size_t begin = a.offset[i], end = a.offset[i + 1];
  const float xi = P[3 * i], yi = P[3 * i + 1], zi = P[3 * i + 2];
  const float h = k.h, density = k.density, spiky = k.spiky, tiny2 = k.coincident2;
  float rho = 0.0f, gx = 0.0f, gy = 0.0f, gz = 0.0f, sum_grad2 = 0.0f;
  int coincident = 0;
#pragma omp simd reduction(+ : rho, gx, gy, gz, sum_grad2, coincident)
  for (std::size_t e = begin; e < end; ++e) {
    const std::uint32_t j = nbr[e];
    const float dx = xi - P[3 * j], dy = yi - P[3 * j + 1], dz = zi - P[3 * j + 2];
    const float r2 = dx * dx + dy * dy + dz * dz;
    const float rlen = std::sqrt(r2);
    const float dl = std::max(h - rlen, 0.0f);
    rho += density * dl * dl * dl;
    const float g = r2 > tiny2 ? spiky * dl * dl / rlen : 0.0f;
    pair_gradient[e] = g;
    coincident += r2 <= tiny2 ? 1 : 0;
    gx += g * dx;
    gy += g * dy;
    gz += g * dz;
    sum_grad2 += g * g * r2;
  }
  return {rho, gx, gy, gz, sum_grad2, coincident};
}

VectorSum deltaSums(const NeighborArrays& a, float coincident2, std::size_t i, const float* lambda,
                    const float* pair_gradient) {
  const float* P = a.position;
  const std::uint32_t* nbr = a.index;
  const std::size_t begin = a.offset[i], end = a.offset[i + 1];
  const float xi = P[3 * i], yi = P[3 * i + 1], zi = P[3 * i + 2];
  const float li = lambda[i];
  float sx = 0.0f, sy = 0.0f, sz = 0.0f;
  int coincident = 0;
#pragma omp simd reduction(+ : sx, sy, sz, coincident)
  for (std::size_t e = begin; e < end; ++e) {
    const std::uint32_t j = nbr[e];
    const float dx = xi - P[3 * j], dy = yi - P[3 * j + 1], dz = zi - P[3 * j + 2];
    const float g = (li + lambda[j]) * pair_gradient[e];
    coincident += dx * dx + dy * dy + dz * dz <= coincident2 ? 1 : 0;
    sx += g * dx;
    sy += g * dy;
    sz += g * dz;
  }
  return {sx, sy, sz, coincident};
}

DensitySum densitySums(const NeighborArrays& a, const PairConstants& k, std::size_t i) {
  const float* P = a.position;
  const std::uint32_t* nbr = a.index;
  const std::size_t begin = a.offset[i], end = a.offset[i + 1];
  const float xi = P[3 * i], yi = P[3 * i + 1], zi = P[3 * i + 2];
  const float h = k.h, h2 = k.h2, density = k.density;
  float rho = 0.0f;
  std::uint32_t count = 0;
#pragma omp simd reduction(+ : rho, count)
  for (std::size_t e = begin; e < end; ++e) {
    const std::uint32_t j = nbr[e];
    const float dx = xi - P[3 * j], dy = yi - P[3 * j + 1], dz = zi - P[3 * j + 2];
    const float r2 = dx * dx + dy * dy + dz * dz;
    const float dl = std::max(h - std::sqrt(r2), 0.0f);
    rho += density * dl * dl * dl;
    count += r2 < h2 ? 1u : 0u;
  }
  return {rho, count};
}

VectorSum xsphSums(const NeighborArrays& a, const PairConstants& k, std::size_t i,
                   const float* velocity, const float* density) {
  const float* P = a.position;
  const std::uint32_t* nbr = a.index;
  const std::size_t begin = a.offset[i], end = a.offset[i + 1];
  const float* V = velocity;
  const float xi = P[3 * i], yi = P[3 * i + 1], zi = P[3 * i + 2];
  const float ux = V[3 * i], uy = V[3 * i + 1], uz = V[3 * i + 2];
  const float h2 = k.h2, poly6 = k.poly6;
  float sx = 0.0f, sy = 0.0f, sz = 0.0f;
#pragma omp simd reduction(+ : sx, sy, sz)
  for (std::size_t e = begin; e < end; ++e) {
    const std::uint32_t j = nbr[e];
    const float dx = xi - P[3 * j], dy = yi - P[3 * j + 1], dz = zi - P[3 * j + 2];
    const float w = std::max(h2 - (dx * dx + dy * dy + dz * dz), 0.0f);
    const float f = poly6 * w * w * w / density[j];  // V_j W_ij
    sx += f * (V[3 * j] - ux);
    sy += f * (V[3 * j + 1] - uy);
    sz += f * (V[3 * j + 2] - uz);
  }
  return {sx, sy, sz, 0};
}

// The image sums: the loops above with x_j replaced by its mirror image m x_j + b.
LambdaSums imageLambdaSums(const NeighborArrays& a, const PairConstants& k, std::size_t i,
                           const Reflection& r) {
  const float* P = a.position;
  const std::uint32_t* nbr = a.index;
  const std::size_t begin = a.offset[i], end = a.offset[i + 1];
  const float xi = P[3 * i], yi = P[3 * i + 1], zi = P[3 * i + 2];
  const float m0 = r.m[0], m1 = r.m[1], m2 = r.m[2], m3 = r.m[3], m4 = r.m[4], m5 = r.m[5],
              m6 = r.m[6], m7 = r.m[7], m8 = r.m[8];
  const float bx = xi - r.b[0], by = yi - r.b[1], bz = zi - r.b[2];
  const float h = k.h, density = k.density, spiky = k.spiky, tiny2 = k.coincident2;
  float rho = 0.0f, gx = 0.0f, gy = 0.0f, gz = 0.0f, sum_grad2 = 0.0f;
  int coincident = 0;
#pragma omp simd reduction(+ : rho, gx, gy, gz, sum_grad2, coincident)
  for (std::size_t e = begin; e < end; ++e) {
    const std::uint32_t j = nbr[e];
    const float x = P[3 * j], y = P[3 * j + 1], z = P[3 * j + 2];
    const float dx = bx - (m0 * x + m1 * y + m2 * z);
    const float dy = by - (m3 * x + m4 * y + m5 * z);
    const float dz = bz - (m6 * x + m7 * y + m8 * z);
    const float r2 = dx * dx + dy * dy + dz * dz;
    const float rlen = std::sqrt(r2);
    const float dl = std::max(h - rlen, 0.0f);
    rho += density * dl * dl * dl;
    const float g = r2 > tiny2 ? spiky * dl * dl / rlen : 0.0f;
    coincident += r2 <= tiny2 ? 1 : 0;
    gx += g * dx;
    gy += g * dy;
    gz += g * dz;
    sum_grad2 += g * g * r2;
  }
  return {rho, gx, gy, gz, sum_grad2, coincident};
}

VectorSum imageDeltaSums(const NeighborArrays& a, const PairConstants& k, std::size_t i,
                         const Reflection& r, const float* lambda) {
  const float* P = a.position;
  const std::uint32_t* nbr = a.index;
  const std::size_t begin = a.offset[i], end = a.offset[i + 1];
  const float xi = P[3 * i], yi = P[3 * i + 1], zi = P[3 * i + 2];
  const float m0 = r.m[0], m1 = r.m[1], m2 = r.m[2], m3 = r.m[3], m4 = r.m[4], m5 = r.m[5],
              m6 = r.m[6], m7 = r.m[7], m8 = r.m[8];
  const float bx = xi - r.b[0], by = yi - r.b[1], bz = zi - r.b[2];
  const float h = k.h, spiky = k.spiky, tiny2 = k.coincident2;
  const float li = lambda[i];
  float sx = 0.0f, sy = 0.0f, sz = 0.0f;
  int coincident = 0;
#pragma omp simd reduction(+ : sx, sy, sz, coincident)
  for (std::size_t e = begin; e < end; ++e) {
    const std::uint32_t j = nbr[e];
    const float x = P[3 * j], y = P[3 * j + 1], z = P[3 * j + 2];
    const float dx = bx - (m0 * x + m1 * y + m2 * z);
    const float dy = by - (m3 * x + m4 * y + m5 * z);
    const float dz = bz - (m6 * x + m7 * y + m8 * z);
    const float r2 = dx * dx + dy * dy + dz * dz;
    const float rlen = std::sqrt(r2);
    const float dl = std::max(h - rlen, 0.0f);
    const float g = r2 > tiny2 ? (li + lambda[j]) * spiky * dl * dl / rlen : 0.0f;
    coincident += r2 <= tiny2 ? 1 : 0;
    sx += g * dx;
    sy += g * dy;
    sz += g * dz;
  }
  return {sx, sy, sz, coincident};
}

DensitySum imageDensitySums(const NeighborArrays& a, const PairConstants& k, std::size_t i,
                            const Reflection& r) {
  const float* P = a.position;
  const std::uint32_t* nbr = a.index;
  const std::size_t begin = a.offset[i], end = a.offset[i + 1];
  const float xi = P[3 * i], yi = P[3 * i + 1], zi = P[3 * i + 2];
  const float m0 = r.m[0], m1 = r.m[1], m2 = r.m[2], m3 = r.m[3], m4 = r.m[4], m5 = r.m[5],
              m6 = r.m[6], m7 = r.m[7], m8 = r.m[8];
  const float bx = xi - r.b[0], by = yi - r.b[1], bz = zi - r.b[2];
  const float h = k.h, h2 = k.h2, density = k.density;
  float rho = 0.0f;
  std::uint32_t count = 0;
#pragma omp simd reduction(+ : rho, count)
  for (std::size_t e = begin; e < end; ++e) {
    const std::uint32_t j = nbr[e];
    const float x = P[3 * j], y = P[3 * j + 1], z = P[3 * j + 2];
    const float dx = bx - (m0 * x + m1 * y + m2 * z);
    const float dy = by - (m3 * x + m4 * y + m5 * z);
    const float dz = bz - (m6 * x + m7 * y + m8 * z);
    const float r2 = dx * dx + dy * dy + dz * dz;
    const float dl = std::max(h - std::sqrt(r2), 0.0f);
    rho += density * dl * dl * dl;
    count += r2 < h2 ? 1u : 0u;
  }
  return {rho, count};
}

}  // namespace PBF_NEIGHBOR_SUMS_NS
}  // namespace pbf
