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

// The x86-64-v3 build runs the hand-written AVX2 copies of the hot loops (WideNeighborSums.h);
// the loops below stay the portable reference.
#if defined(__AVX2__) && defined(__FMA__)
#define PBF_WIDE_NEIGHBOR_SUMS 1
#include "WideNeighborSums.h"
#else
#define PBF_WIDE_NEIGHBOR_SUMS 0
#endif

namespace pbf {
namespace PBF_NEIGHBOR_SUMS_NS {

// Every loop below is branch-free over the neighbour list (masks instead of `if`), so the
// compiler vectorises it; the order of the additions is the compiler's, identical for every
// thread count (each particle's sum is computed by one thread). Details GCC needs (check
// with -fopt-info-vec): a size_t loop index (with a 32-bit one, the store to pair_gradient
// stops vectorisation: the wrapping index makes the addresses non-affine);
// -fno-trapping-math for this file (cmake/core.cmake) so that the division behind the
// coincident-pair mask may run in every lane (NaN and Inf still propagate); and a signed
// neighbour index with -mtune-ctrl=use_gather (cmake/core.cmake) for the AVX2 build to load
// the neighbours with gather instructions: an unsigned 3 j may wrap, which a gather's signed
// 32-bit offsets cannot express, and GCC's generic tuning otherwise assembles each gather
// from eight scalar loads (12 % of a 20k step on Zen 3).

LambdaSums lambdaSums(const NeighborArrays& a, const PairConstants& k, std::size_t i,
                      float* pair_gradient) {
#if PBF_WIDE_NEIGHBOR_SUMS
  return wideLambdaSums(a, k, i, pair_gradient);
#endif
  const float* P = a.position;
  const std::uint32_t* nbr = a.index;
  const std::size_t begin = a.offset[i], end = a.offset[i + 1];
  const float xi = P[3 * i], yi = P[3 * i + 1], zi = P[3 * i + 2];
  const float h = k.h, h2 = k.h2, density = k.density, spiky = k.spiky, tiny2 = k.coincident2;
  float rho = 0.0f, gx = 0.0f, gy = 0.0f, gz = 0.0f, sum_grad2 = 0.0f;
  int coincident = 0;
  std::uint32_t within = 0;
#pragma omp simd reduction(+ : rho, gx, gy, gz, sum_grad2, coincident, within)
  for (std::size_t e = begin; e < end; ++e) {
    const int j = static_cast<int>(nbr[e]);
    const float dx = xi - P[3 * j], dy = yi - P[3 * j + 1], dz = zi - P[3 * j + 2];
    const float r2 = dx * dx + dy * dy + dz * dz;
    const float rlen = std::sqrt(r2);
    const float dl = std::max(h - rlen, 0.0f);
    rho += density * dl * dl * dl;
    const float g = r2 > tiny2 ? spiky * dl * dl / rlen : 0.0f;
    pair_gradient[e - begin] = g;
    coincident += r2 <= tiny2 ? 1 : 0;
    within += r2 < h2 ? 1u : 0u;
    gx += g * dx;
    gy += g * dy;
    gz += g * dz;
    sum_grad2 += g * g * r2;
  }
  return {rho, gx, gy, gz, sum_grad2, coincident, within};
}

VectorSum deltaSums(const NeighborArrays& a, std::size_t i, const float* lambda,
                    const float* pair_gradient) {
#if PBF_WIDE_NEIGHBOR_SUMS
  return wideDeltaSums(a, i, lambda, pair_gradient);
#endif
  const float* P = a.position;
  const std::uint32_t* nbr = a.index;
  const std::size_t begin = a.offset[i], end = a.offset[i + 1];
  const float xi = P[3 * i], yi = P[3 * i + 1], zi = P[3 * i + 2];
  const float li = lambda[i];
  float sx = 0.0f, sy = 0.0f, sz = 0.0f;
#pragma omp simd reduction(+ : sx, sy, sz)
  for (std::size_t e = begin; e < end; ++e) {
    const int j = static_cast<int>(nbr[e]);
    const float dx = xi - P[3 * j], dy = yi - P[3 * j + 1], dz = zi - P[3 * j + 2];
    const float g = (li + lambda[j]) * pair_gradient[e - begin];
    sx += g * dx;
    sy += g * dy;
    sz += g * dz;
  }
  return {sx, sy, sz};
}

DensitySum densitySums(const NeighborArrays& a, const PairConstants& k, std::size_t i) {
#if PBF_WIDE_NEIGHBOR_SUMS
  return wideDensitySums(a, k, i);
#endif
  const float* P = a.position;
  const std::uint32_t* nbr = a.index;
  const std::size_t begin = a.offset[i], end = a.offset[i + 1];
  const float xi = P[3 * i], yi = P[3 * i + 1], zi = P[3 * i + 2];
  const float h = k.h, h2 = k.h2, density = k.density;
  float rho = 0.0f;
  std::uint32_t count = 0;
#pragma omp simd reduction(+ : rho, count)
  for (std::size_t e = begin; e < end; ++e) {
    const int j = static_cast<int>(nbr[e]);
    const float dx = xi - P[3 * j], dy = yi - P[3 * j + 1], dz = zi - P[3 * j + 2];
    const float r2 = dx * dx + dy * dy + dz * dz;
    const float dl = std::max(h - std::sqrt(r2), 0.0f);
    rho += density * dl * dl * dl;
    count += r2 < h2 ? 1u : 0u;
  }
  return {rho, count};
}

VectorSum xsphSums(const NeighborArrays& a, const PairConstants& k, std::size_t i,
                   const float* velocity, const float* density, const float* velocity_slots) {
#if PBF_WIDE_NEIGHBOR_SUMS
  return wideXsphSums(a, k, i, velocity, density, velocity_slots);
#else
  (void)velocity_slots;  // the portable loop gathers
#endif
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
    const int j = static_cast<int>(nbr[e]);
    const float dx = xi - P[3 * j], dy = yi - P[3 * j + 1], dz = zi - P[3 * j + 2];
    const float w = std::max(h2 - (dx * dx + dy * dy + dz * dz), 0.0f);
    const float f = poly6 * w * w * w / density[j];  // V_j W_ij
    sx += f * (V[3 * j] - ux);
    sy += f * (V[3 * j + 1] - uy);
    sz += f * (V[3 * j + 2] - uz);
  }
  return {sx, sy, sz};
}

// The image sums: the loops above with x_j replaced by its mirror image m x_j + b.

namespace {

// x_i minus the mirror image m x_j + b of a neighbour j, for one particle i and one
// reflection: the image loops' shared geometry, in registers. (Internal linkage: each build
// of this file keeps its own copy, see the top of the file.)
struct ImageOffset {
  ImageOffset(const Reflection& r, float xi, float yi, float zi)
      : m0(r.m[0]), m1(r.m[1]), m2(r.m[2]), m3(r.m[3]), m4(r.m[4]), m5(r.m[5]), m6(r.m[6]),
        m7(r.m[7]), m8(r.m[8]), bx(xi - r.b[0]), by(yi - r.b[1]), bz(zi - r.b[2]) {}
  float dx(float x, float y, float z) const { return bx - (m0 * x + m1 * y + m2 * z); }
  float dy(float x, float y, float z) const { return by - (m3 * x + m4 * y + m5 * z); }
  float dz(float x, float y, float z) const { return bz - (m6 * x + m7 * y + m8 * z); }
  float m0, m1, m2, m3, m4, m5, m6, m7, m8, bx, by, bz;
};

}  // namespace

// One reflection (a particle by one wall, the common case): branch-free, vectorised.
// grad_j C_i = -(g (x_i - x_j) + g' (R x_i - x_j)): the image of j seen from i is the image
// of i seen from j, R x_i - x_j = m (x_i - R x_j) for a reflection.
static LambdaSums lambdaSumsWithImage(const NeighborArrays& a, const PairConstants& k, std::size_t i,
                                      const Reflection& r, float* pair_gradient,
                                      float* image_gradient) {
#if PBF_WIDE_NEIGHBOR_SUMS
  return wideLambdaSumsWithImage(a, k, i, r, pair_gradient, image_gradient);
#endif
  const float* P = a.position;
  const std::uint32_t* nbr = a.index;
  const std::size_t begin = a.offset[i], end = a.offset[i + 1];
  const float xi = P[3 * i], yi = P[3 * i + 1], zi = P[3 * i + 2];
  const ImageOffset o(r, xi, yi, zi);
  const float rix = xi - o.dx(xi, yi, zi), riy = yi - o.dy(xi, yi, zi), riz = zi - o.dz(xi, yi, zi);  // R x_i
  const float h = k.h, h2 = k.h2, density = k.density, spiky = k.spiky, tiny2 = k.coincident2;
  float rho = 0.0f, gx = 0.0f, gy = 0.0f, gz = 0.0f, sum_grad2 = 0.0f;
  int coincident = 0;
  std::uint32_t within = 0;
#pragma omp simd reduction(+ : rho, gx, gy, gz, sum_grad2, coincident, within)
  for (std::size_t e = begin; e < end; ++e) {
    const int j = static_cast<int>(nbr[e]);
    const float x = P[3 * j], y = P[3 * j + 1], z = P[3 * j + 2];
    const float dx = xi - x, dy = yi - y, dz = zi - z;
    const float r2 = dx * dx + dy * dy + dz * dz;
    const float rlen = std::sqrt(r2);
    const float dl = std::max(h - rlen, 0.0f);
    const float g = r2 > tiny2 ? spiky * dl * dl / rlen : 0.0f;
    pair_gradient[e - begin] = g;
    coincident += r2 <= tiny2 ? 1 : 0;
    within += r2 < h2 ? 1u : 0u;
    const float ex = o.dx(x, y, z), ey = o.dy(x, y, z), ez = o.dz(x, y, z);
    const float s2 = ex * ex + ey * ey + ez * ez;
    const float slen = std::sqrt(s2);
    const float sl = std::max(h - slen, 0.0f);
    const float gi = s2 > tiny2 ? spiky * sl * sl / slen : 0.0f;
    image_gradient[e - begin] = gi;
    rho += density * (dl * dl * dl + sl * sl * sl);
    gx += g * dx + gi * ex;
    gy += g * dy + gi * ey;
    gz += g * dz + gi * ez;
    const float vx = g * dx + gi * (rix - x), vy = g * dy + gi * (riy - y), vz = g * dz + gi * (riz - z);
    sum_grad2 += vx * vx + vy * vy + vz * vz;
  }
  return {rho, gx, gy, gz, sum_grad2, coincident, within};
}

LambdaSums lambdaSumsWithImages(const NeighborArrays& a, const PairConstants& k, std::size_t i,
                                const Reflection* r, int count, float* pair_gradient,
                                float* image_gradient) {
  if (count == 1) return lambdaSumsWithImage(a, k, i, r[0], pair_gradient, image_gradient);
#if PBF_WIDE_NEIGHBOR_SUMS
  return wideLambdaSumsWithImages(a, k, i, r, count, pair_gradient);
#endif
  // Two or three walls (edges, corners: few particles): the same, scalar over the reflections.
  const float* P = a.position;
  const std::uint32_t* nbr = a.index;
  const float h = k.h, h2 = k.h2, density = k.density, spiky = k.spiky, tiny2 = k.coincident2;
  const float xi = P[3 * i], yi = P[3 * i + 1], zi = P[3 * i + 2];
  float rho = 0.0f, gx = 0.0f, gy = 0.0f, gz = 0.0f, sum_grad2 = 0.0f;
  int coincident = 0;
  std::uint32_t within = 0;
  const std::size_t begin = a.offset[i], end = a.offset[i + 1];
  for (std::size_t e = begin; e < end; ++e) {
    const int j = static_cast<int>(nbr[e]);
    const float x = P[3 * j], y = P[3 * j + 1], z = P[3 * j + 2];
    const float dx = xi - x, dy = yi - y, dz = zi - z;
    const float r2 = dx * dx + dy * dy + dz * dz;
    const float rlen = std::sqrt(r2);
    const float dl = std::max(h - rlen, 0.0f);
    const float g = r2 > tiny2 ? spiky * dl * dl / rlen : 0.0f;
    pair_gradient[e - begin] = g;
    coincident += r2 <= tiny2 ? 1 : 0;
    within += r2 < h2 ? 1u : 0u;
    rho += density * dl * dl * dl;
    gx += g * dx, gy += g * dy, gz += g * dz;
    float vx = g * dx, vy = g * dy, vz = g * dz;
    for (int q = 0; q < count; ++q) {
      const float* m = r[q].m;
      const float ix = m[0] * x + m[1] * y + m[2] * z + r[q].b[0];  // image of j
      const float iy = m[3] * x + m[4] * y + m[5] * z + r[q].b[1];
      const float iz = m[6] * x + m[7] * y + m[8] * z + r[q].b[2];
      const float ex = xi - ix, ey = yi - iy, ez = zi - iz;
      const float s2 = ex * ex + ey * ey + ez * ez;
      if (s2 >= k.h2 || s2 <= tiny2) continue;
      const float slen = std::sqrt(s2);
      const float sl = h - slen;
      const float gi = spiky * sl * sl / slen;
      rho += density * sl * sl * sl;
      gx += gi * ex, gy += gi * ey, gz += gi * ez;
      // R x_i - x_j = m (x_i - image of j)
      vx += gi * (m[0] * ex + m[1] * ey + m[2] * ez);
      vy += gi * (m[3] * ex + m[4] * ey + m[5] * ez);
      vz += gi * (m[6] * ex + m[7] * ey + m[8] * ez);
    }
    sum_grad2 += vx * vx + vy * vy + vz * vz;
  }
  return {rho, gx, gy, gz, sum_grad2, coincident, within};
}
LambdaSums imageLambdaSums(const NeighborArrays& a, const PairConstants& k, std::size_t i,
                           const Reflection& r) {
  const float* P = a.position;
  const std::uint32_t* nbr = a.index;
  const std::size_t begin = a.offset[i], end = a.offset[i + 1];
  const float xi = P[3 * i], yi = P[3 * i + 1], zi = P[3 * i + 2];
  const ImageOffset o(r, xi, yi, zi);
  const float h = k.h, density = k.density, spiky = k.spiky, tiny2 = k.coincident2;
  float rho = 0.0f, gx = 0.0f, gy = 0.0f, gz = 0.0f, sum_grad2 = 0.0f;
  int coincident = 0;
#pragma omp simd reduction(+ : rho, gx, gy, gz, sum_grad2, coincident)
  for (std::size_t e = begin; e < end; ++e) {
    const int j = static_cast<int>(nbr[e]);
    const float x = P[3 * j], y = P[3 * j + 1], z = P[3 * j + 2];
    const float dx = o.dx(x, y, z), dy = o.dy(x, y, z), dz = o.dz(x, y, z);
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
  return {rho, gx, gy, gz, sum_grad2, coincident, 0};
}

VectorSum imageDeltaSums(const NeighborArrays& a, const PairConstants& k, std::size_t i,
                         const Reflection& r, const float* lambda) {
#if PBF_WIDE_NEIGHBOR_SUMS
  return wideImageDeltaSums(a, k, i, r, lambda);
#endif
  const float* P = a.position;
  const std::uint32_t* nbr = a.index;
  const std::size_t begin = a.offset[i], end = a.offset[i + 1];
  const float xi = P[3 * i], yi = P[3 * i + 1], zi = P[3 * i + 2];
  const ImageOffset o(r, xi, yi, zi);
  const float h = k.h, spiky = k.spiky, tiny2 = k.coincident2;
  const float li = lambda[i];
  float sx = 0.0f, sy = 0.0f, sz = 0.0f;
#pragma omp simd reduction(+ : sx, sy, sz)
  for (std::size_t e = begin; e < end; ++e) {
    const int j = static_cast<int>(nbr[e]);
    const float x = P[3 * j], y = P[3 * j + 1], z = P[3 * j + 2];
    const float dx = o.dx(x, y, z), dy = o.dy(x, y, z), dz = o.dz(x, y, z);
    const float r2 = dx * dx + dy * dy + dz * dz;
    const float rlen = std::sqrt(r2);
    const float dl = std::max(h - rlen, 0.0f);
    const float g = r2 > tiny2 ? (li + lambda[j]) * spiky * dl * dl / rlen : 0.0f;
    sx += g * dx;
    sy += g * dy;
    sz += g * dz;
  }
  return {sx, sy, sz};
}

VectorSum deltaSumsWithImage(const NeighborArrays& a, std::size_t i, const Reflection& r,
                             const float* lambda, const float* pair_gradient,
                             const float* image_gradient) {
#if PBF_WIDE_NEIGHBOR_SUMS
  return wideDeltaSumsWithImage(a, i, r, lambda, pair_gradient, image_gradient);
#endif
  const float* P = a.position;
  const std::uint32_t* nbr = a.index;
  const std::size_t begin = a.offset[i], end = a.offset[i + 1];
  const float xi = P[3 * i], yi = P[3 * i + 1], zi = P[3 * i + 2];
  const ImageOffset o(r, xi, yi, zi);
  const float li = lambda[i];
  float sx = 0.0f, sy = 0.0f, sz = 0.0f;
#pragma omp simd reduction(+ : sx, sy, sz)
  for (std::size_t e = begin; e < end; ++e) {
    const int j = static_cast<int>(nbr[e]);
    const float x = P[3 * j], y = P[3 * j + 1], z = P[3 * j + 2];
    const float lij = li + lambda[j];
    const float g = lij * pair_gradient[e - begin], gi = lij * image_gradient[e - begin];
    sx += g * (xi - x) + gi * o.dx(x, y, z);
    sy += g * (yi - y) + gi * o.dy(x, y, z);
    sz += g * (zi - z) + gi * o.dz(x, y, z);
  }
  return {sx, sy, sz};
}

DensitySum imageDensitySums(const NeighborArrays& a, const PairConstants& k, std::size_t i,
                            const Reflection& r) {
#if PBF_WIDE_NEIGHBOR_SUMS
  return wideImageDensitySums(a, k, i, r);
#endif
  const float* P = a.position;
  const std::uint32_t* nbr = a.index;
  const std::size_t begin = a.offset[i], end = a.offset[i + 1];
  const float xi = P[3 * i], yi = P[3 * i + 1], zi = P[3 * i + 2];
  const ImageOffset o(r, xi, yi, zi);
  const float h = k.h, h2 = k.h2, density = k.density;
  float rho = 0.0f;
  std::uint32_t count = 0;
#pragma omp simd reduction(+ : rho, count)
  for (std::size_t e = begin; e < end; ++e) {
    const int j = static_cast<int>(nbr[e]);
    const float x = P[3 * j], y = P[3 * j + 1], z = P[3 * j + 2];
    const float dx = o.dx(x, y, z), dy = o.dy(x, y, z), dz = o.dz(x, y, z);
    const float r2 = dx * dx + dy * dy + dz * dz;
    const float dl = std::max(h - std::sqrt(r2), 0.0f);
    rho += density * dl * dl * dl;
    count += r2 < h2 ? 1u : 0u;
  }
  return {rho, count};
}

bool readsPacked() { return PBF_WIDE_NEIGHBOR_SUMS != 0; }

}  // namespace PBF_NEIGHBOR_SUMS_NS
}  // namespace pbf
