#pragma once
// The inner loop of the neighbour search (NeighborGrid::findNeighbors): of a cell's
// candidates, keep those within the radius of one point, in candidate order.
//
// Two builds of one loop, chosen once per process: a scalar one, and on CPUs with AVX2 one
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

// The scalar build, whatever the CPU (for tests: both builds must keep the same pairs).
std::size_t keepCandidatesWithinScalar(const Candidates& c, float px, float py, float pz, float r2,
                                       std::uint32_t self, std::uint32_t* out);

// Which build runs: "avx2" or "scalar".
const char* candidateFilterVariant();

}  // namespace pbf
