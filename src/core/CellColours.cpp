#include "CellColours.h"

#include "pbf_ros/core/NeighborGrid.h"

namespace pbf {

void CellColours::build(const NeighborGrid& grid) {
  const std::vector<std::uint32_t>& cell = grid.pointCells();
  const std::uint32_t nx = static_cast<std::uint32_t>(grid.dims().x());
  const std::uint32_t ny = static_cast<std::uint32_t>(grid.dims().y());
  by_grid_order_.clear();
  colour_.clear();
  const std::uint32_t n = static_cast<std::uint32_t>(cell.size());
  for (std::uint32_t k = 0; k < n;) {
    std::uint32_t end = k + 1;
    while (end < n && cell[end] == cell[k]) ++end;
    const std::uint32_t dense = cell[k];
    const std::uint32_t x = dense % nx, y = (dense / nx) % ny, z = dense / (nx * ny);
    by_grid_order_.push_back({k, end});
    colour_.push_back(static_cast<std::uint8_t>(x % 3 + 3 * (y % 3) + 9 * (z % 3)));
    k = end;
  }
  // Counting sort by colour (stable: each colour keeps the grid's order).
  start_.fill(0);
  for (const std::uint8_t c : colour_) ++start_[c + 1];
  for (int c = 0; c < kColours; ++c) start_[c + 1] += start_[c];
  cells_.resize(by_grid_order_.size());
  std::array<std::uint32_t, kColours> next{};
  for (int c = 0; c < kColours; ++c) next[c] = start_[c];
  for (std::size_t q = 0; q < by_grid_order_.size(); ++q) cells_[next[colour_[q]]++] = by_grid_order_[q];
}

}  // namespace pbf
