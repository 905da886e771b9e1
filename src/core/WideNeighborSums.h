#pragma once
// The hot neighbour sums of NeighborSums.cpp written out for AVX2 + FMA, eight neighbours at
// a time. Included only by the x86-64-v3 build of NeighborSums.cpp (the build's target keeps
// the portable loops there, which are the reference: test_core_neighbor_sums checks both).
//
// Why by hand: GCC's `omp simd` reductions keep their per-lane sums in a stack array, so
// every pair's additions wait on a store and a load; each list ends in a scalar loop for
// its last 0-7 neighbours (a list has 30-60); and each pair pays a square root and a
// division. Here the sums stay in registers, the last group is masked (loads and stores
// with a lane mask), 1/r comes from the reciprocal square root estimate refined by one
// Newton step (within ~2 float ulps of 1/sqrt), and neighbours are loaded from 16-byte
// slots where the caller packed them (Group; gathered otherwise). Results differ from the
// portable loops at float level only, and are the same for any thread count (one particle,
// one thread, a fixed order of additions).
//
// Conventions the portable loops define and these keep: coincident pairs (r^2 at or below
// coincident2) get no gradient and are counted; a NaN position turns the density sum NaN (the
// step's guard rejects it), so every max() below puts the value second (vmaxps returns its
// second operand when one is NaN).
// Internal linkage throughout: see the top of NeighborSums.cpp.

#include <immintrin.h>

#include <cstddef>
#include <cstdint>

#include "NeighborSums.h"

namespace pbf {
namespace PBF_NEIGHBOR_SUMS_NS {
namespace {

constexpr std::size_t kWidth = 8;

inline __m256 splat(float v) { return _mm256_set1_ps(v); }

// Lanes [e, end) of a group starting at e: all-ones where the lane holds a neighbour.
inline __m256i validLanes(std::size_t e, std::size_t end) {
  const std::size_t left = end - e;
  const int count = left < kWidth ? static_cast<int>(left) : static_cast<int>(kWidth);
  return _mm256_cmpgt_epi32(_mm256_set1_epi32(count), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
}

// Eight neighbours' 16-byte slots (x, y, z, w; NeighborArrays::packed) as x, y, z and w
// vectors: eight 128-bit loads and a 4x4 transpose in each half, cheaper than three gathers
// (the lambda sums of a 20k lattice: 0.97 -> 0.64 ms on an AMD family 26 CPU).
inline void loadPackedSlots(const float* packed, const std::uint32_t* j, __m256& x, __m256& y,
                            __m256& z, __m256& w) {
  const auto pair = [packed](std::uint32_t lo, std::uint32_t hi) {  // slot lo | slot hi
    return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(packed + 4 * std::size_t{lo})),
                                _mm_loadu_ps(packed + 4 * std::size_t{hi}), 1);
  };
  const __m256 t0 = pair(j[0], j[4]), t1 = pair(j[1], j[5]), t2 = pair(j[2], j[6]), t3 = pair(j[3], j[7]);
  const __m256 xy01 = _mm256_unpacklo_ps(t0, t1), zw01 = _mm256_unpackhi_ps(t0, t1);
  const __m256 xy23 = _mm256_unpacklo_ps(t2, t3), zw23 = _mm256_unpackhi_ps(t2, t3);
  x = _mm256_shuffle_ps(xy01, xy23, 0x44);
  y = _mm256_shuffle_ps(xy01, xy23, 0xEE);
  z = _mm256_shuffle_ps(zw01, zw23, 0x44);
  w = _mm256_shuffle_ps(zw01, zw23, 0xEE);
}

// One group of up to eight neighbours: their indices and positions (0 in unused lanes), and
// with packed slots also their w (NeighborArrays::packed; 0 in unused lanes).
struct Group {
  Group(const NeighborArrays& a, std::size_t e, std::size_t end)
      : full(end - e >= kWidth),
        valid(validLanes(e, end)),
        index(full ? _mm256_loadu_si256(reinterpret_cast<const __m256i*>(a.index + e))
                   : _mm256_maskload_epi32(reinterpret_cast<const int*>(a.index + e), valid)),
        triple(_mm256_add_epi32(index, _mm256_slli_epi32(index, 1))),  // 3 j: j's x (j < 2^31 / 3)
        from_slots(a.packed != nullptr) {
    if (!from_slots) {
      x = gatherPacked(a.position, 0), y = gatherPacked(a.position, 1), z = gatherPacked(a.position, 2);
      w = _mm256_setzero_ps();
      return;
    }
    if (full) {
      lanes = a.index + e;
    } else {  // the last group: unused lanes load particle 0's slot, then are cleared
      _mm256_store_si256(reinterpret_cast<__m256i*>(last_lanes), index);
      lanes = last_lanes;
    }
    loadSlots(a.packed, x, y, z, w);
  }
  Group(const Group&) = delete;  // `lanes` may point into the group itself
  // Another slot array (x, y, z, w per particle) at these neighbours, 0 in unused lanes;
  // only for a group built with slots.
  void loadSlots(const float* slots, __m256& sx, __m256& sy, __m256& sz, __m256& sw) const {
    loadPackedSlots(slots, lanes, sx, sy, sz, sw);
    if (lanes != last_lanes) return;
    sx = _mm256_and_ps(sx, validMask()), sy = _mm256_and_ps(sy, validMask());
    sz = _mm256_and_ps(sz, validMask()), sw = _mm256_and_ps(sw, validMask());
  }
  __m256 validMask() const { return _mm256_castsi256_ps(valid); }
  // The group's entries of a per-pair array (0 in unused lanes), and a store to them. Only
  // the last group of a list is masked (it must not touch the next particle's entries):
  // AMD CPUs run a masked store as many micro-ops, and the lambda pass stores once per
  // group (unmasked full groups: a 20k dam break 7-10 % faster on an AMD family 25 CPU).
  __m256 load(const float* pair_values) const {
    return full ? _mm256_loadu_ps(pair_values) : _mm256_maskload_ps(pair_values, valid);
  }
  void store(float* pair_values, __m256 v) const {
    if (full)
      _mm256_storeu_ps(pair_values, v);
    else
      _mm256_maskstore_ps(pair_values, valid, v);
  }
  // A per-particle float array at these neighbours (`fill` in unused lanes).
  __m256 gather(const float* values, float fill = 0.0f) const {
    return _mm256_mask_i32gather_ps(splat(fill), values, index, validMask(), 4);
  }
  // The neighbours' multipliers in the delta-p sums: from the slots' w where the lambda pass
  // put them there (NeighborArrays::packed), else gathered.
  __m256 lambda(const float* values) const { return from_slots ? w : gather(values); }
  // Component c of a packed x,y,z array at these neighbours.
  __m256 gatherPacked(const float* values, int c) const {
    return _mm256_mask_i32gather_ps(_mm256_setzero_ps(), values + c, triple, validMask(), 4);
  }
  bool full;  // all eight lanes are neighbours (declared first: `index` reads it)
  __m256i valid, index, triple;
  __m256 x, y, z, w;
  bool from_slots;
  const std::uint32_t* lanes = nullptr;  // with slots: the eight indices loaded
  alignas(32) std::uint32_t last_lanes[kWidth];
};

// Particle i's own position: from its slot where the caller packed them (every pass packs
// the positions it reads; the Gauss-Seidel sweep moves the slots alone), else from the x,y,z
// array.
struct OwnPosition {
  OwnPosition(const NeighborArrays& a, std::size_t i) {
    const float* p = a.packed != nullptr ? a.packed + 4 * i : a.position + 3 * i;
    x = p[0], y = p[1], z = p[2];
  }
  float x, y, z;
};

// 1 / sqrt(r2) for r2 > 0, and 0 where r2 is 0 (or NaN: then r2 * rinv stays NaN).
inline __m256 inverseLength(__m256 r2) {
  const __m256 y = _mm256_rsqrt_ps(r2);
  const __m256 refined =
      _mm256_mul_ps(y, _mm256_fnmadd_ps(_mm256_mul_ps(splat(0.5f), r2), _mm256_mul_ps(y, y), splat(1.5f)));
  return _mm256_and_ps(refined, _mm256_cmp_ps(r2, _mm256_setzero_ps(), _CMP_GT_OQ));
}

// Sum of the eight lanes in a fixed order.
inline float laneSum(__m256 v) {
  const __m128 s = _mm_add_ps(_mm256_castps256_ps128(v), _mm256_extractf128_ps(v, 1));
  const __m128 t = _mm_add_ps(s, _mm_movehl_ps(s, s));
  return _mm_cvtss_f32(_mm_add_ss(t, _mm_movehdup_ps(t)));
}

inline int laneCount(__m256 mask) { return __builtin_popcount(_mm256_movemask_ps(mask)); }

// A pass's kernel constants in every lane, loaded once per particle: inside the loop the
// compiler would reload them after every store (they could alias the stored arrays).
struct WideConstants {
  explicit WideConstants(const PairConstants& k)
      : h(splat(k.h)), h2(splat(k.h2)), poly6(splat(k.poly6)), density(splat(k.density)),
        spiky(splat(k.spiky)), coincident2(splat(k.coincident2)) {}
  __m256 h, h2, poly6, density, spiky, coincident2;
};

// One group's pairs with particle i: the vectors d = x_i - x_j (or x_i - image of j), r^2,
// (h - r)_+ (0 in unused lanes), which pairs have a direction (r^2 above coincident2), and
// the gradient factor g = spiky (h - r)_+^2 / r (grad = g d; 0 for coincident pairs and
// unused lanes).
struct Pairs {
  Pairs(__m256 x, __m256 y, __m256 z, __m256 valid, const WideConstants& k)
      : dx(x), dy(y), dz(z), r2(_mm256_fmadd_ps(z, z, _mm256_fmadd_ps(y, y, _mm256_mul_ps(x, x)))) {
    const __m256 rinv = inverseLength(r2);
    dl = _mm256_and_ps(_mm256_max_ps(_mm256_setzero_ps(), _mm256_sub_ps(k.h, _mm256_mul_ps(r2, rinv))), valid);
    directed = _mm256_and_ps(_mm256_cmp_ps(r2, k.coincident2, _CMP_GT_OQ), valid);
    g = _mm256_and_ps(_mm256_mul_ps(_mm256_mul_ps(k.spiky, _mm256_mul_ps(dl, dl)), rinv), directed);
  }
  __m256 cube() const { return _mm256_mul_ps(_mm256_mul_ps(dl, dl), dl); }
  __m256 dx, dy, dz, r2, dl, directed, g;
};

inline Pairs directPairs(const Group& n, __m256 xi, __m256 yi, __m256 zi, const WideConstants& k) {
  return Pairs(_mm256_sub_ps(xi, n.x), _mm256_sub_ps(yi, n.y), _mm256_sub_ps(zi, n.z), n.validMask(), k);
}

// What every lambda sum does with its direct pairs besides summing: cache the gradient
// factors for the delta-p pass, count the coincident pairs and the neighbours within h.
struct DirectPairBook {
  void add(const Group& n, const Pairs& p, const WideConstants& k, float* pair_gradient) {
    n.store(pair_gradient, p.g);
    coincident += laneCount(_mm256_andnot_ps(p.directed, n.validMask()));
    within += laneCount(_mm256_and_ps(_mm256_cmp_ps(p.r2, k.h2, _CMP_LT_OQ), n.validMask()));
  }
  int coincident = 0;
  std::uint32_t within = 0;
};

inline LambdaSums wideLambdaSums(const NeighborArrays& a, const PairConstants& k, std::size_t i,
                                 float* pair_gradient) {
  const WideConstants wk(k);
  const std::size_t begin = a.offset[i], end = a.offset[i + 1];
  const OwnPosition own(a, i);
  const __m256 xi = splat(own.x), yi = splat(own.y), zi = splat(own.z);
  __m256 rho = _mm256_setzero_ps(), gx = rho, gy = rho, gz = rho, grad2 = rho;
  DirectPairBook book;
  for (std::size_t e = begin; e < end; e += kWidth) {
    const Group n(a, e, end);
    const Pairs p = directPairs(n, xi, yi, zi, wk);
    book.add(n, p, wk, pair_gradient + (e - begin));
    rho = _mm256_fmadd_ps(wk.density, p.cube(), rho);
    gx = _mm256_fmadd_ps(p.g, p.dx, gx);
    gy = _mm256_fmadd_ps(p.g, p.dy, gy);
    gz = _mm256_fmadd_ps(p.g, p.dz, gz);
    grad2 = _mm256_fmadd_ps(_mm256_mul_ps(p.g, p.g), p.r2, grad2);
  }
  return {laneSum(rho), laneSum(gx), laneSum(gy), laneSum(gz), laneSum(grad2), book.coincident, book.within};
}

inline VectorSum wideDeltaSums(const NeighborArrays& a, std::size_t i, const float* lambda,
                               const float* pair_gradient) {
  const std::size_t begin = a.offset[i], end = a.offset[i + 1];
  const OwnPosition own(a, i);
  const __m256 xi = splat(own.x), yi = splat(own.y), zi = splat(own.z), li = splat(lambda[i]);
  __m256 sx = _mm256_setzero_ps(), sy = sx, sz = sx;
  for (std::size_t e = begin; e < end; e += kWidth) {
    const Group n(a, e, end);
    const __m256 factor = n.load(pair_gradient + (e - begin));  // 0 in unused lanes
    const __m256 g = _mm256_mul_ps(_mm256_add_ps(li, n.lambda(lambda)), factor);
    sx = _mm256_fmadd_ps(g, _mm256_sub_ps(xi, n.x), sx);
    sy = _mm256_fmadd_ps(g, _mm256_sub_ps(yi, n.y), sy);
    sz = _mm256_fmadd_ps(g, _mm256_sub_ps(zi, n.z), sz);
  }
  return {laneSum(sx), laneSum(sy), laneSum(sz)};
}

inline DensitySum wideDensitySums(const NeighborArrays& a, const PairConstants& k, std::size_t i) {
  const WideConstants wk(k);
  const std::size_t begin = a.offset[i], end = a.offset[i + 1];
  const OwnPosition own(a, i);
  const __m256 xi = splat(own.x), yi = splat(own.y), zi = splat(own.z);
  __m256 rho = _mm256_setzero_ps();
  std::uint32_t count = 0;
  for (std::size_t e = begin; e < end; e += kWidth) {
    const Group n(a, e, end);
    const Pairs p = directPairs(n, xi, yi, zi, wk);
    rho = _mm256_fmadd_ps(wk.density, p.cube(), rho);
    count += laneCount(_mm256_and_ps(_mm256_cmp_ps(p.r2, wk.h2, _CMP_LT_OQ), n.validMask()));
  }
  return {laneSum(rho), count};
}

inline VectorSum wideXsphSums(const NeighborArrays& a, const PairConstants& k, std::size_t i,
                              const float* velocity, const float* density, const float* velocity_slots) {
  const WideConstants wk(k);
  const std::size_t begin = a.offset[i], end = a.offset[i + 1];
  const OwnPosition own(a, i);
  const __m256 xi = splat(own.x), yi = splat(own.y), zi = splat(own.z);
  const __m256 ux = splat(velocity[3 * i]), uy = splat(velocity[3 * i + 1]), uz = splat(velocity[3 * i + 2]);
  __m256 sx = _mm256_setzero_ps(), sy = sx, sz = sx;
  for (std::size_t e = begin; e < end; e += kWidth) {
    const Group n(a, e, end);
    const __m256 dx = _mm256_sub_ps(xi, n.x), dy = _mm256_sub_ps(yi, n.y), dz = _mm256_sub_ps(zi, n.z);
    const __m256 r2 = _mm256_fmadd_ps(dz, dz, _mm256_fmadd_ps(dy, dy, _mm256_mul_ps(dx, dx)));
    const __m256 w = _mm256_and_ps(_mm256_max_ps(_mm256_setzero_ps(), _mm256_sub_ps(wk.h2, r2)),
                                   n.validMask());
    __m256 vx, vy, vz, rho;
    if (velocity_slots != nullptr && n.from_slots) {
      n.loadSlots(velocity_slots, vx, vy, vz, rho);
      rho = _mm256_blendv_ps(splat(1.0f), rho, n.validMask());
    } else {
      vx = n.gatherPacked(velocity, 0), vy = n.gatherPacked(velocity, 1), vz = n.gatherPacked(velocity, 2);
      rho = n.gather(density, 1.0f);
    }
    // V_j W_ij; unused lanes divide 0 by 1.
    const __m256 f = _mm256_div_ps(_mm256_mul_ps(_mm256_mul_ps(wk.poly6, w), _mm256_mul_ps(w, w)), rho);
    sx = _mm256_fmadd_ps(f, _mm256_sub_ps(vx, ux), sx);
    sy = _mm256_fmadd_ps(f, _mm256_sub_ps(vy, uy), sy);
    sz = _mm256_fmadd_ps(f, _mm256_sub_ps(vz, uz), sz);
  }
  return {laneSum(sx), laneSum(sy), laneSum(sz)};
}

// x_i minus the mirror image m x_j + b of eight neighbours (ImageOffset in NeighborSums.cpp).
struct WideImageOffset {
  WideImageOffset(const Reflection& r, float xi, float yi, float zi) {
    for (int c = 0; c < 9; ++c) m[c] = splat(r.m[c]);
    bx = splat(xi - r.b[0]), by = splat(yi - r.b[1]), bz = splat(zi - r.b[2]);
  }
  __m256 row(int c, __m256 x, __m256 y, __m256 z) const {
    return _mm256_fmadd_ps(m[3 * c + 2], z, _mm256_fmadd_ps(m[3 * c + 1], y, _mm256_mul_ps(m[3 * c], x)));
  }
  __m256 dx(__m256 x, __m256 y, __m256 z) const { return _mm256_sub_ps(bx, row(0, x, y, z)); }
  __m256 dy(__m256 x, __m256 y, __m256 z) const { return _mm256_sub_ps(by, row(1, x, y, z)); }
  __m256 dz(__m256 x, __m256 y, __m256 z) const { return _mm256_sub_ps(bz, row(2, x, y, z)); }
  __m256 m[9], bx, by, bz;
};

inline Pairs imagePairs(const Group& n, const WideImageOffset& o, const WideConstants& k) {
  return Pairs(o.dx(n.x, n.y, n.z), o.dy(n.x, n.y, n.z), o.dz(n.x, n.y, n.z), n.validMask(), k);
}

// lambdaSumsWithImage of NeighborSums.cpp (one reflection): see there for the equations.
inline LambdaSums wideLambdaSumsWithImage(const NeighborArrays& a, const PairConstants& k,
                                          std::size_t i, const Reflection& r, float* pair_gradient,
                                          float* image_gradient) {
  const WideConstants wk(k);
  const std::size_t begin = a.offset[i], end = a.offset[i + 1];
  const OwnPosition own(a, i);
  const float pxi = own.x, pyi = own.y, pzi = own.z;
  const __m256 xi = splat(pxi), yi = splat(pyi), zi = splat(pzi);
  const WideImageOffset o(r, pxi, pyi, pzi);
  const __m256 rix = _mm256_sub_ps(xi, o.dx(xi, yi, zi)), riy = _mm256_sub_ps(yi, o.dy(xi, yi, zi)),
               riz = _mm256_sub_ps(zi, o.dz(xi, yi, zi));  // R x_i
  __m256 rho = _mm256_setzero_ps(), gx = rho, gy = rho, gz = rho, grad2 = rho;
  DirectPairBook book;
  for (std::size_t e = begin; e < end; e += kWidth) {
    const Group n(a, e, end);
    const Pairs p = directPairs(n, xi, yi, zi, wk);
    book.add(n, p, wk, pair_gradient + (e - begin));
    const Pairs s = imagePairs(n, o, wk);
    n.store(image_gradient + (e - begin), s.g);
    rho = _mm256_fmadd_ps(wk.density, _mm256_add_ps(p.cube(), s.cube()), rho);
    gx = _mm256_fmadd_ps(s.g, s.dx, _mm256_fmadd_ps(p.g, p.dx, gx));
    gy = _mm256_fmadd_ps(s.g, s.dy, _mm256_fmadd_ps(p.g, p.dy, gy));
    gz = _mm256_fmadd_ps(s.g, s.dz, _mm256_fmadd_ps(p.g, p.dz, gz));
    const __m256 vx = _mm256_fmadd_ps(s.g, _mm256_sub_ps(rix, n.x), _mm256_mul_ps(p.g, p.dx));
    const __m256 vy = _mm256_fmadd_ps(s.g, _mm256_sub_ps(riy, n.y), _mm256_mul_ps(p.g, p.dy));
    const __m256 vz = _mm256_fmadd_ps(s.g, _mm256_sub_ps(riz, n.z), _mm256_mul_ps(p.g, p.dz));
    grad2 = _mm256_fmadd_ps(vz, vz, _mm256_fmadd_ps(vy, vy, _mm256_fmadd_ps(vx, vx, grad2)));
  }
  return {laneSum(rho), laneSum(gx), laneSum(gy), laneSum(gz), laneSum(grad2), book.coincident, book.within};
}

// deltaSumsWithImage of NeighborSums.cpp.
inline VectorSum wideDeltaSumsWithImage(const NeighborArrays& a, std::size_t i, const Reflection& r,
                                        const float* lambda, const float* pair_gradient,
                                        const float* image_gradient) {
  const std::size_t begin = a.offset[i], end = a.offset[i + 1];
  const OwnPosition own(a, i);
  const float pxi = own.x, pyi = own.y, pzi = own.z;
  const __m256 xi = splat(pxi), yi = splat(pyi), zi = splat(pzi), li = splat(lambda[i]);
  const WideImageOffset o(r, pxi, pyi, pzi);
  __m256 sx = _mm256_setzero_ps(), sy = sx, sz = sx;
  for (std::size_t e = begin; e < end; e += kWidth) {
    const Group n(a, e, end);
    const __m256 lij = _mm256_add_ps(li, n.lambda(lambda));
    const __m256 g = _mm256_mul_ps(lij, n.load(pair_gradient + (e - begin)));
    const __m256 gi = _mm256_mul_ps(lij, n.load(image_gradient + (e - begin)));
    sx = _mm256_fmadd_ps(gi, o.dx(n.x, n.y, n.z), _mm256_fmadd_ps(g, _mm256_sub_ps(xi, n.x), sx));
    sy = _mm256_fmadd_ps(gi, o.dy(n.x, n.y, n.z), _mm256_fmadd_ps(g, _mm256_sub_ps(yi, n.y), sy));
    sz = _mm256_fmadd_ps(gi, o.dz(n.x, n.y, n.z), _mm256_fmadd_ps(g, _mm256_sub_ps(zi, n.z), sz));
  }
  return {laneSum(sx), laneSum(sy), laneSum(sz)};
}

// lambdaSumsWithImages of NeighborSums.cpp for two or three reflections (a particle at an
// edge or a corner of the container): the direct pair and each image of j, grad_j C_i summed
// over them before squaring. Only the direct pairs' factors are cached (the delta-p pass
// recomputes the images' for these few particles).
inline LambdaSums wideLambdaSumsWithImages(const NeighborArrays& a, const PairConstants& k,
                                           std::size_t i, const Reflection* r, int count,
                                           float* pair_gradient) {
  const WideConstants wk(k);
  const std::size_t begin = a.offset[i], end = a.offset[i + 1];
  const OwnPosition own(a, i);
  const float pxi = own.x, pyi = own.y, pzi = own.z;
  const __m256 xi = splat(pxi), yi = splat(pyi), zi = splat(pzi);
  __m256 rho = _mm256_setzero_ps(), gx = rho, gy = rho, gz = rho, grad2 = rho;
  DirectPairBook book;
  for (std::size_t e = begin; e < end; e += kWidth) {
    const Group n(a, e, end);
    const Pairs p = directPairs(n, xi, yi, zi, wk);
    book.add(n, p, wk, pair_gradient + (e - begin));
    __m256 cubes = p.cube();
    __m256 vx = _mm256_mul_ps(p.g, p.dx), vy = _mm256_mul_ps(p.g, p.dy), vz = _mm256_mul_ps(p.g, p.dz);
    gx = _mm256_add_ps(gx, vx), gy = _mm256_add_ps(gy, vy), gz = _mm256_add_ps(gz, vz);
    for (int q = 0; q < count; ++q) {
      const WideImageOffset o(r[q], pxi, pyi, pzi);
      const Pairs s = imagePairs(n, o, wk);
      cubes = _mm256_add_ps(cubes, _mm256_and_ps(s.cube(), s.directed));  // as the scalar loop
      gx = _mm256_fmadd_ps(s.g, s.dx, gx), gy = _mm256_fmadd_ps(s.g, s.dy, gy), gz = _mm256_fmadd_ps(s.g, s.dz, gz);
      // R x_i - x_j (see lambdaSumsWithImage in NeighborSums.cpp)
      vx = _mm256_fmadd_ps(s.g, _mm256_sub_ps(_mm256_sub_ps(xi, o.dx(xi, yi, zi)), n.x), vx);
      vy = _mm256_fmadd_ps(s.g, _mm256_sub_ps(_mm256_sub_ps(yi, o.dy(xi, yi, zi)), n.y), vy);
      vz = _mm256_fmadd_ps(s.g, _mm256_sub_ps(_mm256_sub_ps(zi, o.dz(xi, yi, zi)), n.z), vz);
    }
    rho = _mm256_fmadd_ps(wk.density, cubes, rho);
    grad2 = _mm256_fmadd_ps(vz, vz, _mm256_fmadd_ps(vy, vy, _mm256_fmadd_ps(vx, vx, grad2)));
  }
  return {laneSum(rho), laneSum(gx), laneSum(gy), laneSum(gz), laneSum(grad2), book.coincident, book.within};
}

// imageDensitySums of NeighborSums.cpp: the density of i's neighbours' images under one
// reflection. Scalar, it gathered each neighbour's x, y, z and took a square root per pair:
// a particle by a wall cost about twice its direct sums in every density pass.
inline DensitySum wideImageDensitySums(const NeighborArrays& a, const PairConstants& k, std::size_t i,
                                       const Reflection& r) {
  const WideConstants wk(k);
  const std::size_t begin = a.offset[i], end = a.offset[i + 1];
  const OwnPosition own(a, i);
  const WideImageOffset o(r, own.x, own.y, own.z);
  __m256 rho = _mm256_setzero_ps();
  std::uint32_t count = 0;
  for (std::size_t e = begin; e < end; e += kWidth) {
    const Group n(a, e, end);
    const Pairs s = imagePairs(n, o, wk);
    rho = _mm256_fmadd_ps(wk.density, s.cube(), rho);
    count += laneCount(_mm256_and_ps(_mm256_cmp_ps(s.r2, wk.h2, _CMP_LT_OQ), n.validMask()));
  }
  return {laneSum(rho), count};
}

// imageDeltaSums of NeighborSums.cpp: sum_j (lambda_i + lambda_j) grad W(x_i - image_j) under
// one reflection, gradients recomputed (particles at edges and corners).
inline VectorSum wideImageDeltaSums(const NeighborArrays& a, const PairConstants& k, std::size_t i,
                                    const Reflection& r, const float* lambda) {
  const WideConstants wk(k);
  const std::size_t begin = a.offset[i], end = a.offset[i + 1];
  const OwnPosition own(a, i);
  const float pxi = own.x, pyi = own.y, pzi = own.z;
  const WideImageOffset o(r, pxi, pyi, pzi);
  const __m256 li = splat(lambda[i]);
  __m256 sx = _mm256_setzero_ps(), sy = sx, sz = sx;
  for (std::size_t e = begin; e < end; e += kWidth) {
    const Group n(a, e, end);
    const Pairs s = imagePairs(n, o, wk);
    const __m256 g = _mm256_mul_ps(_mm256_add_ps(li, n.lambda(lambda)), s.g);
    sx = _mm256_fmadd_ps(g, s.dx, sx);
    sy = _mm256_fmadd_ps(g, s.dy, sy);
    sz = _mm256_fmadd_ps(g, s.dz, sz);
  }
  return {laneSum(sx), laneSum(sy), laneSum(sz)};
}

}  // namespace
}  // namespace PBF_NEIGHBOR_SUMS_NS
}  // namespace pbf
