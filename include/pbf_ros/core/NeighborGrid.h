#pragma once
// Fixed-radius neighbour search on a uniform grid (cell size >= search radius).
//
// build() counting-sorts the points by cell, with cells ranked in Morton (z-curve) order,
// and returns the permutation so the caller can keep its particle arrays in that order:
// neighbours in space are then neighbours in memory. findNeighbors() writes compact (CSR)
// lists of every point within the radius: no cap, nothing silently dropped. Results do not
// depend on the number of OpenMP threads.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

namespace pbf {

// Where a NeighborGrid's cells start on one axis: by default the origin snaps to multiples
// of 8 cells; with an anchor, a cell starts exactly at the domain's bound on `axis` (its
// lower bound, or its upper one when `at_max`), so that the layer of points at that bound
// lies in the first cell of a block of 2 x 2 x 2 cells. The Gauss-Seidel order projects a
// block's cells top first (BlockColours.h): anchored at the fluid's bottom, its bottom
// layer is projected after the layers above it.
struct GridAnchor {
  int axis = -1;  // 0, 1, 2; -1: none
  bool at_max = false;
};

class NeighborGrid {
 public:
  // Sorts `points` into cells of size `cell_size` covering `domain` (points outside it go
  // to the border cells, which keeps the search exact: clamping cell coordinates never
  // separates two cells that were adjacent). An empty domain means the points' bounds.
  // Returns order: sorted slot k holds the point that was at index order[k].
  const std::vector<std::uint32_t>& build(const std::vector<Eigen::Vector3f>& points,
                                          float cell_size,
                                          const Eigen::AlignedBox3f& domain = {},
                                          const GridAnchor& anchor = {});

  // CSR lists for the points of the last build, given in sorted order: neighbours of i
  // are indices()[offsets()[i] .. offsets()[i+1]), excluding i, every j with
  // |p_i - p_j| < radius, in ascending j. Requires radius <= cell_size.
  // Throws std::length_error (leaving empty lists) beyond max_pairs entries (at most
  // kMaxPairs), which bounds the memory (the lists and the threads' buffers, each at most
  // twice the lists) and keeps the 32-bit offsets from overflowing: a fluid has ~30-60
  // neighbours per point, only a collapsed state (thousands of points in one spot) gets there.
  void findNeighbors(const std::vector<Eigen::Vector3f>& sorted_points, float radius,
                     std::size_t max_pairs = kMaxPairs);

  const std::vector<std::uint32_t>& offsets() const { return offsets_; }
  const std::vector<std::uint32_t>& indices() const { return indices_; }
  std::size_t cellCount() const { return rank_.size(); }
  // The grid of the last build: its dimensions in cells, and the cell of each sorted point
  // (dense index x + dims.x (y + dims.y z)); the points of a cell are consecutive.
  const Eigen::Vector3i& dims() const { return dims_; }
  const std::vector<std::uint32_t>& pointCells() const { return point_cell_; }

  // Interleaves the low 21 bits of x, y, z (x in the lowest bit).
  static constexpr std::size_t kMaxPairs = std::size_t(1) << 28;

  static std::uint64_t morton3(std::uint32_t x, std::uint32_t y, std::uint32_t z);

 private:
  Eigen::Vector3i cellOf(const Eigen::Vector3f& p) const;
  void rankCellsInMortonOrder();

  float cell_size_ = 1.0f;
  Eigen::Vector3f origin_ = Eigen::Vector3f::Zero();
  Eigen::Vector3i dims_ = Eigen::Vector3i::Zero();
  std::vector<std::uint32_t> rank_;        // dense cell index -> Morton rank (cached per dims)
  std::vector<std::uint32_t> cell_start_;  // by rank, size cells + 1: first sorted point
  std::vector<std::uint32_t> point_cell_;  // dense cell index of each sorted point
  std::vector<std::uint32_t> order_;
  std::vector<std::uint32_t> offsets_, indices_;
  std::vector<std::uint32_t> unsorted_cell_;  // scratch
  std::vector<float> soa_x_, soa_y_, soa_z_;   // findNeighbors()' points, one array per axis
  // Per-thread buffers of findNeighbors, kept between calls: no allocation per step.
  struct ThreadScratch {
    std::vector<std::uint32_t> list;       // the thread's block of neighbour lists
    std::vector<std::uint32_t> candidates;  // one cell's candidate set
    std::vector<float> x, y, z;             // and their positions
  };
  std::vector<ThreadScratch> thread_scratch_;
  std::vector<std::size_t> thread_filled_;  // filled entries of each list
  std::vector<std::size_t> block_base_;     // where each thread's block starts
  std::vector<std::uint32_t> next_slot_;    // build()'s counting sort
};

}  // namespace pbf
