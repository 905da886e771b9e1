#include "BlockColours.h"

#include "pbf_ros/core/NeighborGrid.h"

namespace pbf {

void BlockColours::build(const NeighborGrid& grid) {
  const std::vector<std::uint32_t>& cell = grid.pointCells();
  const std::uint32_t nx = static_cast<std::uint32_t>(grid.dims().x());
  const std::uint32_t ny = static_cast<std::uint32_t>(grid.dims().y());
  by_grid_order_.clear();
  colour_.clear();
  const std::uint32_t n = static_cast<std::uint32_t>(cell.size());
  for (std::uint32_t k = 0; k < n;) {
    std::uint32_t end = k + 1;
    const std::uint32_t dense = cell[k];
    const std::uint32_t bx = dense % nx / 2, by = (dense / nx) % ny / 2, bz = dense / (nx * ny) / 2;
    // The block's cells are contiguous in the grid's Morton order (a Morton code over 2 is
    // the code of the coordinates over 2): extend the run to the block's last point.
    auto sameBlock = [&](std::uint32_t other) {
      return other % nx / 2 == bx && (other / nx) % ny / 2 == by && other / (nx * ny) / 2 == bz;
    };
    while (end < n && (cell[end] == cell[end - 1] || sameBlock(cell[end]))) ++end;
    by_grid_order_.push_back({k, end});
    colour_.push_back(static_cast<std::uint8_t>((bx & 1) + 2 * (by & 1) + 4 * (bz & 1)));
    k = end;
  }
  // Counting sort by colour (stable: each colour keeps the grid's order).
  start_.fill(0);
  for (const std::uint8_t c : colour_) ++start_[c + 1];
  for (int c = 0; c < kColours; ++c) start_[c + 1] += start_[c];
  blocks_.resize(by_grid_order_.size());
  std::array<std::uint32_t, kColours> next{};
  for (int c = 0; c < kColours; ++c) next[c] = start_[c];
  for (std::size_t q = 0; q < by_grid_order_.size(); ++q) blocks_[next[colour_[q]]++] = by_grid_order_[q];
}

}  // namespace pbf
