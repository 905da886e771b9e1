#pragma once
// The order of a parallel Gauss-Seidel sweep (GaussSeidelSweep.cpp): the occupied blocks of
// 2 x 2 x 2 cells of a NeighborGrid in phases, one per colour that has blocks (the block's
// coordinates modulo 2 on each axis: at most 8), each phase's blocks independent of one
// another, so that a sweep can run in parallel and still give the same result for any
// thread count.
//
// Why blocks of one colour are independent: two of them are at least one block (two cells,
// >= 2 search radii) apart, so no particle is within the search radius of a particle in
// each, at the positions the lists were built from. A constraint reads and moves only its
// own particle and that particle's list: two constraints of one colour in different blocks
// touch disjoint particles, however far the solve has moved them since (the lists are index
// sets). Each block's particles are taken one after another by one thread; so the order of
// every projection is fixed by the grid and gravity alone. Each phase ends at a barrier.
//
// Top first, along gravity. Gauss-Seidel leaves the least residual where it projects last,
// and a column's load travels down: a layer projected before the layers above it is pushed
// back into compression by them. So within a block the cells go top first, and within a
// cell the points highest first (a cell holds two layers of a lattice); the grid anchors
// its cells at the fluid's bottom (GridAnchor), so that the floor's layer is the last one
// of its block. The phases keep the grid's Morton order, colour by colour over the whole
// fluid. In that order with a block's bottom cells first (session 22), a resting tank ended
// with its floor, edges and corners at 2.5-4x the average error over rho0; whole layers of
// blocks taken top first were as even, but their extra barriers cost 20 % (doc/validation.md
// §2, "Top first").
// Points clamped into the grid's border cells (NeighborGrid::build) lie beyond them, which
// only moves them farther from the other blocks of their colour.

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

namespace pbf {

class NeighborGrid;

class BlockColours {
 public:
  static constexpr int kColours = 8;
  struct Block {
    std::uint32_t begin, end;  // the block's entries of order(): its points, top cell first
  };

  // The order of a block's 8 cells (octant x&1 + 2 (y&1) + 4 (z&1)) when projected: the
  // highest along -gravity first; ties (a level floor's cells, or no gravity) in descending
  // octant, so that gravity along -z gives the Morton order reversed.
  static std::array<std::uint8_t, 8> octantsTopFirst(float gx, float gy, float gz);

  // From the grid's last build, its points (in the grid's sorted order) and gravity: every
  // occupied block in the phase of its colour, each phase's blocks in the grid's (Morton)
  // order, each block's cells top first, each cell's points highest first. O(points).
  void build(const NeighborGrid& grid, const std::vector<Eigen::Vector3f>& points,
             const Eigen::Vector3f& gravity);

  std::size_t phases() const { return phase_start_.size() - 1; }
  // The blocks of phase p: [first(p), first(p) + count(p)).
  const Block* first(std::size_t phase) const { return blocks_.data() + phase_start_[phase]; }
  std::size_t count(std::size_t phase) const { return phase_start_[phase + 1] - phase_start_[phase]; }

  // The sorted points in projection order: a block's points are order()[begin .. end).
  const std::uint32_t* order() const { return order_.data(); }

  // Thread t's share of phase p's blocks when `threads` project them: the run
  // [begin, end) of indices into first(p) whose particles are about a 1/threads part of
  // the phase's particles. Shares by block count left one thread with 14 % more particles
  // than the other in the flowing dam break (blocks hold 1 to ~64), and the other waited
  // at every barrier. A run, not scattered blocks: each thread stays in one part of the
  // fluid (GaussSeidelSweep.cpp).
  std::pair<std::size_t, std::size_t> share(std::size_t phase, int thread, int threads) const;

 private:
  struct Ranked {
    std::uint8_t colour;
    Block block;
  };
  std::vector<Ranked> by_grid_order_;   // scratch: the occupied blocks as the grid sorted them
  std::vector<Block> blocks_;           // by phase
  std::vector<std::uint32_t> before_;   // per entry of blocks_: its phase's particles before it
  std::vector<std::size_t> phase_start_{0};
  std::vector<std::uint32_t> order_;    // every sorted point, each block's cells top first
};

}  // namespace pbf
