#include "BlockColours.h"

#include <algorithm>

#include "pbf_ros/core/NeighborGrid.h"

namespace pbf {

namespace {

// Cells of up to this many points sort their points by height from a key array on the stack
// (a cell of a fluid at rest density holds ~8 at h = 2d).
constexpr std::uint32_t kSmallCell = 64;

// A cell's (or a block's) coordinates from the grid's dense index x + nx (y + ny z).
struct DenseCells {
  std::uint32_t nx, ny;
  std::array<std::uint32_t, 3> coords(std::uint32_t dense) const {
    return {dense % nx, (dense / nx) % ny, dense / (nx * ny)};
  }
};

// Which of the 8 parities (x&1 + 2 (y&1) + 4 (z&1)) coordinates have: a cell's octant in
// its block, or a block's colour.
std::uint8_t parity(const std::array<std::uint32_t, 3>& c) {
  return static_cast<std::uint8_t>((c[0] & 1) + 2 * (c[1] & 1) + 4 * (c[2] & 1));
}

}  // namespace

std::array<std::uint8_t, 8> BlockColours::octantsTopFirst(float gx, float gy, float gz) {
  std::array<std::uint8_t, 8> octants;
  for (int o = 0; o < 8; ++o) octants[o] = static_cast<std::uint8_t>(7 - o);
  // Height of an octant's offset along -gravity; ties in descending octant. Not
  // std::stable_sort: it allocates a buffer, and a warm step allocates nothing.
  auto height = [&](std::uint8_t o) { return -(gx * (o & 1) + gy * ((o >> 1) & 1) + gz * ((o >> 2) & 1)); };
  std::sort(octants.begin(), octants.end(), [&](std::uint8_t a, std::uint8_t b) {
    return height(a) != height(b) ? height(a) > height(b) : a > b;
  });
  return octants;
}

void BlockColours::build(const NeighborGrid& grid, const std::vector<Eigen::Vector3f>& points,
                         const Eigen::Vector3f& gravity) {
  const std::vector<std::uint32_t>& cell = grid.pointCells();
  const DenseCells cells{static_cast<std::uint32_t>(grid.dims().x()), static_cast<std::uint32_t>(grid.dims().y())};
  auto blockOf = [&](std::uint32_t dense) {
    std::array<std::uint32_t, 3> c = cells.coords(dense);
    for (std::uint32_t& v : c) v /= 2;
    return c;
  };
  by_grid_order_.clear();
  const std::uint32_t n = static_cast<std::uint32_t>(cell.size());
  for (std::uint32_t k = 0; k < n;) {
    std::uint32_t end = k + 1;
    const std::array<std::uint32_t, 3> block = blockOf(cell[k]);
    // The block's cells are contiguous in the grid's Morton order (a Morton code over 2 is
    // the code of the coordinates over 2): extend the run to the block's last point.
    while (end < n && (cell[end] == cell[end - 1] || blockOf(cell[end]) == block)) ++end;
    by_grid_order_.push_back({parity(block), {k, end}});
    k = end;
  }

  // Each block's points in projection order: its cells by octant, top first, and a cell's
  // points (two layers of a lattice) highest first; ties by index, so the order is fixed.
  const std::array<std::uint8_t, 8> octants = octantsTopFirst(gravity.x(), gravity.y(), gravity.z());
  std::array<std::uint8_t, 8> rank{};
  for (int r = 0; r < 8; ++r) rank[octants[r]] = static_cast<std::uint8_t>(r);
  order_.resize(n);
  const std::ptrdiff_t blocks = static_cast<std::ptrdiff_t>(by_grid_order_.size());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t q = 0; q < blocks; ++q) {
    const Block b = by_grid_order_[q].block;
    // The block's cells are runs of its points (at most 8): their octants, ranked.
    struct Run {
      std::uint32_t rank, begin, end;
    };
    std::array<Run, 8> runs;
    int run_count = 0;
    for (std::uint32_t p = b.begin; p < b.end;) {
      const std::uint32_t c = cell[p];
      std::uint32_t e = p + 1;
      while (e < b.end && cell[e] == c) ++e;
      runs[run_count++] = {rank[parity(cells.coords(c))], p, e};
      p = e;
    }
    std::sort(runs.begin(), runs.begin() + run_count, [](const Run& x, const Run& y) { return x.rank < y.rank; });
    // Each point's height is computed once, not in every comparison (the comparisons' dot
    // products were most of this build's time): the keys sort as the points would.
    struct Keyed {
      float height;
      std::uint32_t point;
    };
    auto keyOf = [&](std::uint32_t p) { return Keyed{-gravity.dot(points[p]), p}; };
    auto higher = [](const Keyed& a, const Keyed& c) {
      return a.height != c.height ? a.height > c.height : a.point > c.point;
    };
    std::array<Keyed, kSmallCell> keys;
    std::uint32_t filled = b.begin;
    for (int r = 0; r < run_count; ++r) {
      const std::uint32_t size = runs[r].end - runs[r].begin;
      if (size > kSmallCell) {
        // A degenerate cloud (every particle at one point, a stress case) can put them all in
        // one cell: the same order, sorted in place.
        const std::uint32_t first = filled;
        for (std::uint32_t p = runs[r].begin; p < runs[r].end; ++p) order_[filled++] = p;
        std::sort(order_.begin() + first, order_.begin() + filled, [&](std::uint32_t a, std::uint32_t c) {
          return higher(keyOf(a), keyOf(c));
        });
        continue;
      }
      for (std::uint32_t q = 0; q < size; ++q) keys[q] = keyOf(runs[r].begin + q);
      std::sort(keys.begin(), keys.begin() + size, higher);
      for (std::uint32_t q = 0; q < size; ++q) order_[filled++] = keys[q].point;
    }
  }

  // Counting sort by colour (stable: each colour keeps the grid's order).
  std::array<std::size_t, kColours + 1> colour_start{};
  for (const Ranked& r : by_grid_order_) ++colour_start[r.colour + 1];
  for (int c = 0; c < kColours; ++c) colour_start[c + 1] += colour_start[c];
  blocks_.resize(by_grid_order_.size());
  before_.resize(by_grid_order_.size());
  std::array<std::size_t, kColours> next_slot;
  for (int c = 0; c < kColours; ++c) next_slot[c] = colour_start[c];
  for (const Ranked& r : by_grid_order_) blocks_[next_slot[r.colour]++] = r.block;
  phase_start_.assign(1, 0);
  for (int c = 0; c < kColours; ++c) {
    if (colour_start[c + 1] == colour_start[c]) continue;
    std::uint32_t sum = 0;
    for (std::size_t q = colour_start[c]; q < colour_start[c + 1]; ++q) {
      before_[q] = sum;
      sum += blocks_[q].end - blocks_[q].begin;
    }
    phase_start_.push_back(colour_start[c + 1]);
  }
}

std::pair<std::size_t, std::size_t> BlockColours::share(std::size_t phase, int thread, int threads) const {
  const std::size_t first = phase_start_[phase], last = phase_start_[phase + 1];
  if (first == last) return {0, 0};
  const std::uint64_t total = std::uint64_t{before_[last - 1]} + (blocks_[last - 1].end - blocks_[last - 1].begin);
  // The first block of the phase whose particles before it reach the share's start.
  auto boundary = [&](int t) -> std::size_t {
    const std::uint64_t target = total * static_cast<std::uint64_t>(t) / static_cast<std::uint64_t>(threads);
    const auto it = std::lower_bound(before_.begin() + first, before_.begin() + last, target,
                                     [](std::uint32_t b, std::uint64_t v) { return b < v; });
    return static_cast<std::size_t>(it - (before_.begin() + first));
  };
  return {boundary(thread), thread + 1 == threads ? last - first : boundary(thread + 1)};
}

}  // namespace pbf
