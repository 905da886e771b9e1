// Experiment (session 18, not shipped): what one correction of a fixed-geometry density solve
// would cost against one shipped constraint iteration, both written for AVX2 like the
// shipped neighbour sums. doc/validation.md §2, "Fixed geometry without the
// relaxation", has the figures and what they mean.
//
//   shipped:  the lambda sums (kernel, gradient factor cached per pair) and the delta-p sums
//             (WideNeighborSums.h, as the solver runs them for a particle away from walls);
//   frozen, scalar factor: the linearised constraint c_i = C*_i + sum_j g_ij d_ij.(dx_i - dx_j)
//             from the cached factor g, the fixed positions and the neighbours' dx (two slot
//             loads per neighbour), then the same delta-p sums;
//   frozen, stored gradient: the pair's gradient stored as three floats, so c_i gathers only
//             dx_j and the delta-p sums only lambda_j.
// It first checks that the three compute the same sums (against a scalar sum in double), then
// times them. On a 20k-particle cubic lattice (40 x 25 x 20, jittered by 2 % of d, no walls), medians of
// 7 runs of 50 after 20 warm-up runs, three rounds. (Since session 25 the shipped sums take
// particle i's row of the per-pair arrays, pg + off[i], not the whole array.) Build and run
// from the repository root:
//   g++ -O2 -std=c++17 -march=x86-64-v3 -mtune-ctrl=use_gather -fno-trapping-math -fopenmp \
//       -Isrc/core -Iinclude doc/experiments/frozen_correction_bench.cpp -o /tmp/frozen_correction_bench
//   /tmp/frozen_correction_bench 1; /tmp/frozen_correction_bench 2     # threads
#define PBF_NEIGHBOR_SUMS_NS neighbor_sums_v3
#include "WideNeighborSums.h"
#include <omp.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

using namespace pbf;
using namespace pbf::neighbor_sums_v3;

namespace pbf { namespace neighbor_sums_v3 { namespace {
// c_i = sum_j g_ij d_ij . (dx_i - dx_j): the linearised constraint's change, positions and
// dx from slots (x,y,z,_), g from the cache.
inline float wideLinearSums(const NeighborArrays& a, std::size_t i, const float* dx_slots,
                            const float* pair_gradient) {
  const std::size_t begin = a.offset[i], end = a.offset[i + 1];
  const __m256 xi = splat(a.position[3 * i]), yi = splat(a.position[3 * i + 1]), zi = splat(a.position[3 * i + 2]);
  const __m256 ux = splat(dx_slots[4 * i]), uy = splat(dx_slots[4 * i + 1]), uz = splat(dx_slots[4 * i + 2]);
  __m256 c = _mm256_setzero_ps();
  for (std::size_t e = begin; e < end; e += kWidth) {
    const Group n(a, e, end);
    __m256 vx, vy, vz, vw;
    n.loadSlots(dx_slots, vx, vy, vz, vw);
    const __m256 g = n.load(pair_gradient + e);
    const __m256 dot = _mm256_fmadd_ps(_mm256_sub_ps(zi, n.z), _mm256_sub_ps(uz, vz),
                       _mm256_fmadd_ps(_mm256_sub_ps(yi, n.y), _mm256_sub_ps(uy, vy),
                       _mm256_mul_ps(_mm256_sub_ps(xi, n.x), _mm256_sub_ps(ux, vx))));
    c = _mm256_fmadd_ps(g, dot, c);
  }
  return laneSum(c);
}
// The same with each pair's gradient stored as three floats (no position gather).
inline float wideLinearSumsStored(const NeighborArrays& a, std::size_t i, const float* dx_slots,
                                  const float* gx_, const float* gy_, const float* gz_) {
  const std::size_t begin = a.offset[i], end = a.offset[i + 1];
  const __m256 ux = splat(dx_slots[4 * i]), uy = splat(dx_slots[4 * i + 1]), uz = splat(dx_slots[4 * i + 2]);
  NeighborArrays b = a;
  b.packed = dx_slots;
  __m256 c = _mm256_setzero_ps();
  for (std::size_t e = begin; e < end; e += kWidth) {
    const Group n(b, e, end);  // dx from the slots
    const __m256 gx = n.load(gx_ + e), gy = n.load(gy_ + e), gz = n.load(gz_ + e);
    c = _mm256_fmadd_ps(gz, _mm256_sub_ps(uz, n.z), _mm256_fmadd_ps(gy, _mm256_sub_ps(uy, n.y),
        _mm256_fmadd_ps(gx, _mm256_sub_ps(ux, n.x), c)));
  }
  return laneSum(c);
}
inline VectorSum wideDeltaStored(const NeighborArrays& a, std::size_t i, const float* lambda_slots,
                                 const float* gx_, const float* gy_, const float* gz_) {
  const std::size_t begin = a.offset[i], end = a.offset[i + 1];
  const __m256 li = splat(lambda_slots[4 * i + 3]);
  __m256 sx = _mm256_setzero_ps(), sy = sx, sz = sx;
  for (std::size_t e = begin; e < end; e += kWidth) {
    const __m256i valid = validLanes(e, end);
    const bool full = end - e >= kWidth;
    const __m256i index = full ? _mm256_loadu_si256(reinterpret_cast<const __m256i*>(a.index + e))
                               : _mm256_maskload_epi32(reinterpret_cast<const int*>(a.index + e), valid);
    const __m256 lj = _mm256_mask_i32gather_ps(_mm256_setzero_ps(), lambda_slots + 3, _mm256_slli_epi32(index, 2),
                                               _mm256_castsi256_ps(valid), 4);
    const __m256 l = _mm256_add_ps(li, lj);
    const __m256 gx = full ? _mm256_loadu_ps(gx_ + e) : _mm256_maskload_ps(gx_ + e, valid);
    const __m256 gy = full ? _mm256_loadu_ps(gy_ + e) : _mm256_maskload_ps(gy_ + e, valid);
    const __m256 gz = full ? _mm256_loadu_ps(gz_ + e) : _mm256_maskload_ps(gz_ + e, valid);
    sx = _mm256_fmadd_ps(l, gx, sx); sy = _mm256_fmadd_ps(l, gy, sy); sz = _mm256_fmadd_ps(l, gz, sz);
  }
  return {laneSum(sx), laneSum(sy), laneSum(sz)};
}
}}}

int main(int argc, char** argv) {
  const int threads = argc > 1 ? std::atoi(argv[1]) : 1;
  omp_set_num_threads(threads);
  const float d = 0.02f, h = 2 * d;
  const int nx = 40, ny = 25, nz = 20;
  const std::size_t n = std::size_t(nx) * ny * nz;
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> jit(-0.02f * d, 0.02f * d);
  std::vector<float> pos(3 * n);
  for (int z = 0; z < nz; ++z) for (int y = 0; y < ny; ++y) for (int x = 0; x < nx; ++x) {
    const std::size_t i = (std::size_t(z) * ny + y) * nx + x;
    pos[3 * i] = x * d + jit(rng); pos[3 * i + 1] = y * d + jit(rng); pos[3 * i + 2] = z * d + jit(rng);
  }
  // Neighbour lists (within 1.02 h, as a search would keep; the lattice's cube of +-2).
  std::vector<std::uint32_t> off(n + 1, 0), idx;
  for (int z = 0; z < nz; ++z) for (int y = 0; y < ny; ++y) for (int x = 0; x < nx; ++x) {
    const std::size_t i = (std::size_t(z) * ny + y) * nx + x;
    for (int c = -2; c <= 2; ++c) for (int b = -2; b <= 2; ++b) for (int a = -2; a <= 2; ++a) {
      if (!a && !b && !c) continue;
      const int X = x + a, Y = y + b, Z = z + c;
      if (X < 0 || Y < 0 || Z < 0 || X >= nx || Y >= ny || Z >= nz) continue;
      const std::size_t j = (std::size_t(Z) * ny + Y) * nx + X;
      float r2 = 0; for (int k = 0; k < 3; ++k) { float t = pos[3*i+k] - pos[3*j+k]; r2 += t * t; }
      if (r2 < h * h) idx.push_back(std::uint32_t(j));
    }
    off[i + 1] = idx.size();
  }
  std::vector<float> s1(4 * n), s2(4 * n), s3(4 * n, 0.0f), pg(idx.size());
  for (std::size_t i = 0; i < n; ++i) { for (int k = 0; k < 3; ++k) s1[4*i+k] = s2[4*i+k] = pos[3*i+k]; s1[4*i+3] = 0; s2[4*i+3] = 0; }
  std::vector<float> lam(n, 0.0f), cstar(n), diag(n, 1.0f);
  const float m = 1000 * d * d * d;
  const PairConstants k{h, h * h, 0.0f, m * 15.0f / (float(M_PI) * std::pow(h, 6.0f)),
                        m / 1000 * -45.0f / (float(M_PI) * std::pow(h, 6.0f)), 1e-12f};
  const float self_density = k.density * h * h * h;  // m W(0); the mass is not normalised
  NeighborArrays arr{pos.data(), off.data(), idx.data(), s1.data()};
  NeighborArrays arr2{pos.data(), off.data(), idx.data(), s2.data()};
  std::vector<float> outx(3 * n);  // the shipped iteration's delta-p, kept so it is not optimised away
  auto shipped = [&]() {
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      const LambdaSums s = wideLambdaSums(arr, k, i, pg.data() + off[i]);
      const float rho = s.rho + self_density;  // the sums leave the particle itself out
      const float C = std::max(rho / 1000 - 1.0f, 0.0f);
      const float l = -C / (s.sum_grad2 + s.gx * s.gx + s.gy * s.gy + s.gz * s.gz + 1e-3f);
      s2[4 * i + 3] = lam[i] = l; diag[i] = s.sum_grad2 + 1e-3f; cstar[i] = rho / 1000 - 1.0f;
    }
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      const VectorSum v = wideDeltaSums(arr2, i, lam.data(), pg.data() + off[i]);
      outx[3 * i] = v.x; outx[3 * i + 1] = v.y; outx[3 * i + 2] = v.z;
    }
  };
  auto frozen = [&]() {
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      const float c = cstar[i] + wideLinearSums(arr, i, s3.data(), pg.data());
      lam[i] = s2[4 * i + 3] += -std::max(c, 0.0f) / diag[i];
    }
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      const VectorSum v = wideDeltaSums(arr2, i, lam.data(), pg.data() + off[i]);
      s3[4 * i] = v.x; s3[4 * i + 1] = v.y; s3[4 * i + 2] = v.z;
    }
  };
  std::vector<float> GX(idx.size()), GY(idx.size()), GZ(idx.size());
  auto stored = [&]() {
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      const float c = cstar[i] + wideLinearSumsStored(arr, i, s3.data(), GX.data(), GY.data(), GZ.data());
      lam[i] = s2[4 * i + 3] += -std::max(c, 0.0f) / diag[i];
    }
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      const VectorSum v = wideDeltaStored(arr2, i, s2.data(), GX.data(), GY.data(), GZ.data());
      s3[4 * i] = v.x; s3[4 * i + 1] = v.y; s3[4 * i + 2] = v.z;
    }
  };
  auto time = [&](auto&& f) {
    for (int w = 0; w < 20; ++w) f();
    std::vector<double> t;
    for (int r = 0; r < 7; ++r) {
      auto t0 = std::chrono::steady_clock::now();
      for (int w = 0; w < 50; ++w) f();
      t.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / 50);
    }
    std::sort(t.begin(), t.end());
    return t;
  };
  shipped();  // fills the cached factors, lambda, the diagonal and C*
  // Each pair's gradient, from the factors the lambda sums just cached.
  for (std::size_t i = 0; i < n; ++i)
    for (std::uint32_t e = off[i]; e < off[i + 1]; ++e) {
      const std::uint32_t j = idx[e];
      GX[e] = pg[e] * (pos[3*i] - pos[3*j]); GY[e] = pg[e] * (pos[3*i+1] - pos[3*j+1]); GZ[e] = pg[e] * (pos[3*i+2] - pos[3*j+2]);
    }
  // The three loops must compute the same linearised constraint: checked against a scalar
  // sum in double after a few corrections have moved dx off zero.
  for (int w = 0; w < 3; ++w) frozen();
  double worst = 0.0, scale = 0.0, delta_worst = 0.0, delta_scale = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    double ref = 0.0;
    for (std::uint32_t e = off[i]; e < off[i + 1]; ++e) {
      const std::uint32_t j = idx[e];
      for (int c = 0; c < 3; ++c)
        ref += double(pg[e]) * (pos[3 * i + c] - pos[3 * j + c]) * (double(s3[4 * i + c]) - s3[4 * j + c]);
    }
    const double a = wideLinearSums(arr, i, s3.data(), pg.data());
    const double b = wideLinearSumsStored(arr, i, s3.data(), GX.data(), GY.data(), GZ.data());
    worst = std::max({worst, std::abs(a - ref), std::abs(b - ref)});
    scale = std::max(scale, std::abs(ref));
    // And the two delta-p loops (cached factor and fixed positions / stored gradient).
    const VectorSum u = wideDeltaSums(arr2, i, lam.data(), pg.data() + off[i]);
    const VectorSum v = wideDeltaStored(arr2, i, s2.data(), GX.data(), GY.data(), GZ.data());
    delta_worst = std::max({delta_worst, double(std::abs(u.x - v.x)), double(std::abs(u.y - v.y)),
                            double(std::abs(u.z - v.z))});
    delta_scale = std::max({delta_scale, double(std::abs(u.x)), double(std::abs(u.y)), double(std::abs(u.z))});
  }
  std::printf("linearised sums against double: largest difference %.2e of a largest value %.2e\n", worst, scale);
  std::printf("delta-p sums, stored against cached: largest difference %.2e of a largest value %.2e\n",
              delta_worst, delta_scale);
  if (!(worst <= 1e-4 * scale) || scale == 0.0 || !(delta_worst <= 1e-4 * delta_scale) || delta_scale == 0.0)
    return 1;
  for (int round = 0; round < 3; ++round) {
    auto a = time(shipped), b = time(frozen), c = time(stored);
    std::printf("threads %d, %zu particles, %.1f neighbours: shipped iteration %.3f ms, frozen correction (scalar factor) %.3f ms = %.2f, (stored gradient) %.3f ms = %.2f\n",
                threads, n, double(idx.size()) / n, a[3], b[3], b[3] / a[3], c[3], c[3] / a[3]);
  }
  return 0;
}
