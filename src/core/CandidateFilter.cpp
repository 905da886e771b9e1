#include "CandidateFilter.h"

#include <array>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define PBF_CANDIDATE_FILTER_AVX2 1
#endif

namespace pbf {

namespace {

std::size_t keepScalar(const Candidates& c, float px, float py, float pz, float r2,
                       std::uint32_t self, std::uint32_t* out) {
  std::size_t kept = 0;
  for (std::size_t k = 0; k < c.count; ++k) {
    const float dx = c.x[k] - px, dy = c.y[k] - py, dz = c.z[k] - pz;
    out[kept] = c.index[k];  // branch-free: written always, kept when it passes
    kept += (dx * dx + dy * dy + dz * dz < r2) & (c.index[k] != self);
  }
  return kept;
}

// The larger of a and b as the x86 max instruction takes it: b when either is NaN.
inline float maxLikeMaxps(float a, float b) { return a > b ? a : b; }

// How far p lies outside [l, h] along one axis; 0 when the box's bound is NaN (a NaN point of
// the cell: then every candidate is kept, as the wide build keeps them).
inline float gapToBox(float p, float l, float h) { return maxLikeMaxps(maxLikeMaxps(l - p, p - h), 0.0f); }

// The squared distance of (px, py, pz) to the box, rounded as keepScalar rounds a distance.
inline float squaredDistanceToBox(float px, float py, float pz, const float lo[3], const float hi[3]) {
  const float gx = gapToBox(px, lo[0], hi[0]), gy = gapToBox(py, lo[1], hi[1]), gz = gapToBox(pz, lo[2], hi[2]);
  return gx * gx + gy * gy + gz * gz;
}

std::size_t appendNearBoxScalar(const float* x, const float* y, const float* z, std::uint32_t begin,
                                std::uint32_t end, const float lo[3], const float hi[3], float r2,
                                const CandidateBuffer& out, std::size_t at) {
  for (std::uint32_t k = begin; k < end; ++k) {
    out.x[at] = x[k], out.y[at] = y[k], out.z[at] = z[k], out.index[at] = k;  // branch-free
    at += squaredDistanceToBox(x[k], y[k], z[k], lo, hi) < r2;
  }
  return at;
}

#ifdef PBF_CANDIDATE_FILTER_AVX2

// For each 8-bit mask of kept lanes, the lanes to gather, lowest first, one byte each.
constexpr std::array<std::uint64_t, 256> makeCompressTable() {
  std::array<std::uint64_t, 256> table{};
  for (int mask = 0; mask < 256; ++mask) {
    std::uint64_t lanes = 0;
    int filled = 0;
    for (int lane = 0; lane < 8; ++lane)
      if (mask & (1 << lane)) lanes |= std::uint64_t(lane) << (8 * filled++);
    table[mask] = lanes;
  }
  return table;
}
constexpr std::array<std::uint64_t, 256> kCompressTable = makeCompressTable();

// No "fma" in the target: the squared distance is rounded exactly as in keepScalar.
__attribute__((target("avx2,popcnt"))) std::size_t keepAvx2(const Candidates& c, float px, float py,
                                                             float pz, float r2, std::uint32_t self,
                                                             std::uint32_t* out) {
  const __m256 vx = _mm256_set1_ps(px), vy = _mm256_set1_ps(py), vz = _mm256_set1_ps(pz);
  const __m256 vr2 = _mm256_set1_ps(r2);
  const __m256i vself = _mm256_set1_epi32(static_cast<int>(self));
  std::size_t kept = 0;
  for (std::size_t k = 0; k < c.count; k += 8) {
    const __m256 dx = _mm256_sub_ps(_mm256_loadu_ps(c.x + k), vx);
    const __m256 dy = _mm256_sub_ps(_mm256_loadu_ps(c.y + k), vy);
    const __m256 dz = _mm256_sub_ps(_mm256_loadu_ps(c.z + k), vz);
    const __m256 d2 = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(dx, dx), _mm256_mul_ps(dy, dy)),
                                    _mm256_mul_ps(dz, dz));
    const __m256i index = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(c.index + k));
    const int near = _mm256_movemask_ps(_mm256_cmp_ps(d2, vr2, _CMP_LT_OQ));
    const int is_self = _mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(index, vself)));
    // Lanes past count hold +infinity (never near); their index lanes are masked out too.
    const int mask = near & ~is_self & 0xff;
    const __m256i lanes =
        _mm256_cvtepu8_epi32(_mm_cvtsi64_si128(static_cast<long long>(kCompressTable[mask])));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + kept),
                        _mm256_permutevar8x32_epi32(index, lanes));
    kept += static_cast<std::size_t>(__builtin_popcount(static_cast<unsigned>(mask)));
  }
  return kept;
}

// How far p lies outside [l, h] along one axis, eight lanes at a time (as gapToBox).
__attribute__((target("avx2"))) inline __m256 gapAvx2(__m256 p, __m256 l, __m256 h) {
  return _mm256_max_ps(_mm256_max_ps(_mm256_sub_ps(l, p), _mm256_sub_ps(p, h)), _mm256_setzero_ps());
}

// Eight points at a time, packed as keepAvx2 packs; lanes at or past `end` are never kept.
__attribute__((target("avx2,popcnt"))) std::size_t appendNearBoxAvx2(
    const float* x, const float* y, const float* z, std::uint32_t begin, std::uint32_t end,
    const float lo[3], const float hi[3], float r2, const CandidateBuffer& out, std::size_t at) {
  const __m256 lox = _mm256_set1_ps(lo[0]), loy = _mm256_set1_ps(lo[1]), loz = _mm256_set1_ps(lo[2]);
  const __m256 hix = _mm256_set1_ps(hi[0]), hiy = _mm256_set1_ps(hi[1]), hiz = _mm256_set1_ps(hi[2]);
  const __m256 vr2 = _mm256_set1_ps(r2);
  const __m256i lane_offsets = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  for (std::uint32_t k = begin; k < end; k += 8) {
    const __m256 px = _mm256_loadu_ps(x + k), py = _mm256_loadu_ps(y + k), pz = _mm256_loadu_ps(z + k);
    const __m256 gx = gapAvx2(px, lox, hix), gy = gapAvx2(py, loy, hiy), gz = gapAvx2(pz, loz, hiz);
    const __m256 d2 = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(gx, gx), _mm256_mul_ps(gy, gy)),
                                    _mm256_mul_ps(gz, gz));
    const std::uint32_t left = end - k;
    const int valid = left >= 8 ? 0xff : (1 << left) - 1;
    const int mask = _mm256_movemask_ps(_mm256_cmp_ps(d2, vr2, _CMP_LT_OQ)) & valid;
    const __m256i lanes =
        _mm256_cvtepu8_epi32(_mm_cvtsi64_si128(static_cast<long long>(kCompressTable[mask])));
    const __m256i index = _mm256_add_epi32(_mm256_set1_epi32(static_cast<int>(k)), lane_offsets);
    _mm256_storeu_ps(out.x + at, _mm256_permutevar8x32_ps(px, lanes));
    _mm256_storeu_ps(out.y + at, _mm256_permutevar8x32_ps(py, lanes));
    _mm256_storeu_ps(out.z + at, _mm256_permutevar8x32_ps(pz, lanes));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out.index + at), _mm256_permutevar8x32_epi32(index, lanes));
    at += static_cast<std::size_t>(__builtin_popcount(static_cast<unsigned>(mask)));
  }
  return at;
}

bool cpuRunsAvx2() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("popcnt");
}

#endif

using FilterFn = std::size_t (*)(const Candidates&, float, float, float, float, std::uint32_t,
                                 std::uint32_t*);
using BoxFilterFn = std::size_t (*)(const float*, const float*, const float*, std::uint32_t,
                                    std::uint32_t, const float*, const float*, float,
                                    const CandidateBuffer&, std::size_t);

// Both loops of one build, so that they are always wide or scalar together. Chosen on first
// use (a function-local static: thread-safe, no static-initialisation order).
struct Builds {
  FilterFn keep;
  BoxFilterFn near_box;
};
const Builds& chosenBuilds() {
  static const Builds builds = [] {
#ifdef PBF_CANDIDATE_FILTER_AVX2
    if (cpuRunsAvx2()) return Builds{keepAvx2, appendNearBoxAvx2};
#endif
    return Builds{keepScalar, appendNearBoxScalar};
  }();
  return builds;
}

}  // namespace

std::size_t appendCandidatesNearBox(const float* x, const float* y, const float* z,
                                    std::uint32_t begin, std::uint32_t end, const float lo[3],
                                    const float hi[3], float r2, const CandidateBuffer& out,
                                    std::size_t at) {
  return chosenBuilds().near_box(x, y, z, begin, end, lo, hi, r2, out, at);
}

std::size_t appendCandidatesNearBoxScalar(const float* x, const float* y, const float* z,
                                          std::uint32_t begin, std::uint32_t end, const float lo[3],
                                          const float hi[3], float r2, const CandidateBuffer& out,
                                          std::size_t at) {
  return appendNearBoxScalar(x, y, z, begin, end, lo, hi, r2, out, at);
}

std::size_t keepCandidatesWithin(const Candidates& c, float px, float py, float pz, float r2,
                                 std::uint32_t self, std::uint32_t* out) {
  return chosenBuilds().keep(c, px, py, pz, r2, self, out);
}

std::size_t keepCandidatesWithinScalar(const Candidates& c, float px, float py, float pz, float r2,
                                       std::uint32_t self, std::uint32_t* out) {
  return keepScalar(c, px, py, pz, r2, self, out);
}

const char* candidateFilterVariant() {
#ifdef PBF_CANDIDATE_FILTER_AVX2
  return chosenBuilds().keep == keepAvx2 ? "avx2" : "scalar";
#else
  return "scalar";
#endif
}

}  // namespace pbf
