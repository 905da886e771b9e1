#pragma once
// The occupied cells of a NeighborGrid in 27 colours (the cell's coordinates modulo 3 on each
// axis), so that a Gauss-Seidel sweep can run in parallel and still give the same result for
// any thread count (GaussSeidelSweep.cpp).
//
// Why 27 colours make the cells of one colour independent: two cells of a colour are at
// least two cells (>= 2 search radii) apart, so no particle is within the search radius of
// a particle in each, at the positions the lists were built from. A constraint reads and
// moves only its own particle and that particle's list: two constraints of one colour in
// different cells touch disjoint particles, however far the solve has moved them since (the
// lists are index sets). Each cell's particles are taken one after another by one thread,
// in memory order; so the order of every projection is fixed by the grid alone.
// Points clamped into the grid's border cells (NeighborGrid::build) lie beyond them, which
// only moves them farther from the other cells of their colour.

#include <array>
#include <cstdint>
#include <vector>

namespace pbf {

class NeighborGrid;

class CellColours {
 public:
  static constexpr int kColours = 27;
  struct Cell {
    std::uint32_t begin, end;  // the cell's sorted points
  };

  // From the grid's last build: every occupied cell, grouped by colour, each colour's cells
  // in the grid's (Morton) order. O(points).
  void build(const NeighborGrid& grid);

  // The cells of colour c: [first(c), first(c) + count(c)).
  const Cell* first(int colour) const { return cells_.data() + start_[colour]; }
  std::size_t count(int colour) const { return start_[colour + 1] - start_[colour]; }

 private:
  std::vector<Cell> by_grid_order_;  // scratch: the occupied cells as the grid sorted them
  std::vector<std::uint8_t> colour_;  // of each of those
  std::vector<Cell> cells_;           // by colour
  std::array<std::uint32_t, kColours + 1> start_{};
};

}  // namespace pbf
