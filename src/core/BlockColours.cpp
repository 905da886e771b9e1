#include "BlockColours.h"

#include <algorithm>

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
  before_.resize(blocks_.size());
  for (int c = 0; c < kColours; ++c) {
    std::uint32_t sum = 0;
    for (std::uint32_t q = start_[c]; q < start_[c + 1]; ++q) {
      before_[q] = sum;
      sum += blocks_[q].end - blocks_[q].begin;
    }
  }
}

std::pair<std::size_t, std::size_t> BlockColours::share(int colour, int thread, int threads) const {
  const std::uint32_t first = start_[colour], last = start_[colour + 1];
  if (first == last) return {0, 0};
  const std::uint64_t total = std::uint64_t{before_[last - 1]} + (blocks_[last - 1].end - blocks_[last - 1].begin);
  // The first block of the colour whose particles before it reach the share's start.
  auto boundary = [&](int t) -> std::size_t {
    const std::uint64_t target = total * static_cast<std::uint64_t>(t) / static_cast<std::uint64_t>(threads);
    const auto it = std::lower_bound(before_.begin() + first, before_.begin() + last, target,
                                     [](std::uint32_t b, std::uint64_t v) { return b < v; });
    return static_cast<std::size_t>(it - (before_.begin() + first));
  };
  return {boundary(thread), thread + 1 == threads ? last - first : boundary(thread + 1)};
}

}  // namespace pbf
