#pragma once
// The inner loops of the neighbour search (NeighborGrid::findNeighbors): gather a cell's
// candidates, the points near the box around the cell's own points, and of those keep the
// ones within the radius of one point, in candidate order.
//
// Two builds of each loop, chosen once per process: a scalar one, and on CPUs with AVX2 one
// that tests eight candidates at a time and packs the kept ones with a permutation (a
// "compress" store, which AVX2 lacks as an instruction). Both compute the squared distance
// with the same multiplications and additions in the same order, without FMA, so they keep
// exactly the same pairs: the lists, and so every result, are identical on every CPU.

#include <cstddef>
#include <cstdint>

namespace pbf {

// Candidate positions as separate x, y, z arrays of `count` entries, readable (not
// necessarily meaningful) up to count rounded up to a multiple of kCandidatePadding; the
// padding entries must be +infinity, so that they are never kept.
struct Candidates {
  const float *x, *y, *z;
  const std::uint32_t* index;  // the candidates' point indices, ascending
  std::size_t count;
};
constexpr std::size_t kCandidatePadding = 8;

// Writes to `out` the index of every candidate c with |c - p|^2 < r2 and index != self, in
// candidate order, and returns how many. `out` must have room for count + kCandidatePadding
// entries (the wide build stores whole groups of eight).
std::size_t keepCandidatesWithin(const Candidates& c, float px, float py, float pz, float r2,
                                 std::uint32_t self, std::uint32_t* out);

// Where a cell's candidate set is written: separate x, y, z arrays and the point indices.
struct CandidateBuffer {
  float *x, *y, *z;
  std::uint32_t* index;
};

// The box [lo, hi] bounds one cell's points. Appends to `out`, from position `at` on, every
// point k in [begin, end) of the arrays x, y, z whose squared distance to the box is below
// r2, in index order, and returns the new count. A point within the radius of any point in
// the box is always kept: the distance to the box is rounded the way keepCandidatesWithin
// rounds the distance to a point, and it is never larger (float subtraction, products and
// sums are monotonic). The arrays must be readable up to end rounded up to a multiple of
// kCandidatePadding past begin, and `out` must have room for at + (end - begin) +
// kCandidatePadding entries.
std::size_t appendCandidatesNearBox(const float* x, const float* y, const float* z,
                                    std::uint32_t begin, std::uint32_t end, const float lo[3],
                                    const float hi[3], float r2, const CandidateBuffer& out,
                                    std::size_t at);

// The scalar builds, whatever the CPU (for tests: both builds must keep the same points).
std::size_t appendCandidatesNearBoxScalar(const float* x, const float* y, const float* z,
                                          std::uint32_t begin, std::uint32_t end, const float lo[3],
                                          const float hi[3], float r2, const CandidateBuffer& out,
                                          std::size_t at);
std::size_t keepCandidatesWithinScalar(const Candidates& c, float px, float py, float pz, float r2,
                                       std::uint32_t self, std::uint32_t* out);

// Which build runs (of both loops): "avx2" or "scalar".
const char* candidateFilterVariant();

}  // namespace pbf
