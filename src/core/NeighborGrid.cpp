#include "pbf_ros/core/NeighborGrid.h"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <limits>
#include <string>
#include <numeric>
#include <stdexcept>

#include "CandidateFilter.h"

namespace pbf {

std::uint64_t NeighborGrid::morton3(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
  auto spread = [](std::uint64_t v) {
    v &= 0x1fffff;
    v = (v | v << 32) & 0x1f00000000ffffULL;
    v = (v | v << 16) & 0x1f0000ff0000ffULL;
    v = (v | v << 8) & 0x100f00f00f00f00fULL;
    v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
    v = (v | v << 2) & 0x1249249249249249ULL;
    return v;
  };
  return spread(x) | (spread(y) << 1) | (spread(z) << 2);
}

Eigen::Vector3i NeighborGrid::cellOf(const Eigen::Vector3f& p) const {
  Eigen::Vector3i c;
  for (int a = 0; a < 3; ++a) {
    // Clamp in float first: a far-away (or huge) coordinate must not overflow the int.
    const float f = std::floor((p[a] - origin_[a]) / cell_size_);
    c[a] = static_cast<int>(std::clamp(f, 0.0f, static_cast<float>(dims_[a] - 1)));
  }
  return c;
}

void NeighborGrid::rankCellsInMortonOrder() {
  const std::size_t n = static_cast<std::size_t>(dims_.prod());
  std::vector<std::pair<std::uint64_t, std::uint32_t>> codes(n);
  for (int z = 0; z < dims_.z(); ++z)
    for (int y = 0; y < dims_.y(); ++y)
      for (int x = 0; x < dims_.x(); ++x) {
        const std::uint32_t dense = x + dims_.x() * (y + dims_.y() * z);
        codes[dense] = {morton3(x, y, z), dense};
      }
  std::sort(codes.begin(), codes.end());
  rank_.resize(n);
  for (std::uint32_t r = 0; r < n; ++r) rank_[codes[r].second] = r;
}

const std::vector<std::uint32_t>& NeighborGrid::build(const std::vector<Eigen::Vector3f>& points,
                                                      float cell_size,
                                                      const Eigen::AlignedBox3f& domain,
                                                      const GridAnchor& anchor) {
  if (!(cell_size > 0.0f)) throw std::invalid_argument("NeighborGrid: cell_size must be > 0");
  const std::size_t n = points.size();
  Eigen::AlignedBox3f box = domain;
  if (box.isEmpty()) {
    for (const auto& p : points) box.extend(p);
    if (box.isEmpty()) box = Eigen::AlignedBox3f(Eigen::Vector3f::Zero(), Eigen::Vector3f::Zero());
  }
  // The dense rank table costs memory and time per cell, so the grid is capped at a few
  // cells per point (a degenerate cloud, one point far away, must not explode it); coarser
  // cells stay exact, only slower. Origin and size snap to blocks of 8 cells so that a
  // moving cloud rarely changes the dimensions and the cached Morton ranks stay valid.
  if (!box.min().allFinite() || !box.max().allFinite())
    throw std::invalid_argument("NeighborGrid: points or domain are not finite");
  constexpr int kBlock = 8;
  const double max_cells = std::max<double>(8.0 * n, 32768.0);
  float cs = cell_size;
  Eigen::Vector3f lo, hi;
  Eigen::Vector3i dims;
  for (int coarsen = 0;; ++coarsen) {
    if (coarsen > 120) throw std::invalid_argument("NeighborGrid: domain too large for a grid");
    const float block = kBlock * cs;
    lo = (box.min() / block).array().floor() * block;
    hi = (box.max() / block).array().floor() * block + block;
    dims = ((hi - lo) / cs).array().round().cast<int>().max(1);
    if (dims.cast<double>().prod() <= max_cells && (hi - lo).allFinite()) break;
    cs *= 2.0f;
  }
  if (anchor.axis >= 0 && anchor.axis < 3) {
    // Shifted by less than a block of 8 cells: the grid still covers the box, and its
    // dimensions (and the cached Morton ranks) stay as they are.
    const int a = anchor.axis;
    lo[a] += anchor.at_max ? box.max()[a] - hi[a] : box.min()[a] - lo[a];
  }
  origin_ = lo;
  if (dims != dims_ || rank_.empty()) {
    dims_ = dims;
    rankCellsInMortonOrder();
  }
  cell_size_ = cs;
  const std::size_t cells = rank_.size();

  // Counting sort by Morton rank of the cell. Serial count and scatter keep it stable, so
  // the order only depends on the input, never on the thread count.
  unsorted_cell_.resize(n);
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3i c = cellOf(points[i]);
    unsorted_cell_[i] = c.x() + dims_.x() * (c.y() + dims_.y() * c.z());
  }
  cell_start_.assign(cells + 1, 0);
  for (std::size_t i = 0; i < n; ++i) ++cell_start_[rank_[unsorted_cell_[i]] + 1];
  std::partial_sum(cell_start_.begin(), cell_start_.end(), cell_start_.begin());
  order_.resize(n);
  point_cell_.resize(n);
  {
    std::vector<std::uint32_t>& next = next_slot_;
    next.assign(cell_start_.begin(), cell_start_.end() - 1);
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint32_t dense = unsorted_cell_[i];
      const std::uint32_t slot = next[rank_[dense]]++;
      order_[slot] = static_cast<std::uint32_t>(i);
      point_cell_[slot] = dense;
    }
  }
  return order_;
}

void NeighborGrid::findNeighbors(const std::vector<Eigen::Vector3f>& pts, float radius,
                                 std::size_t max_pairs) {
  const std::size_t n = pts.size();
  max_pairs = std::min(max_pairs, kMaxPairs);
  if (n != order_.size()) throw std::invalid_argument("NeighborGrid: points differ from build");
  if (radius > cell_size_ * 1.0001f)
    throw std::invalid_argument("NeighborGrid: radius larger than the cell size");
  const float r2 = radius * radius;
  const int nx = dims_.x(), ny = dims_.y(), nz = dims_.z();
  struct Range { std::uint32_t begin, end; };

  // Each thread fills the lists of one contiguous block of particles into its own buffer;
  // the buffers are then concatenated in block order, so the CSR arrays are identical for
  // any thread count.
  offsets_.resize(n + 1);
  auto& scratch = thread_scratch_;
  auto& block_base = block_base_;
  std::atomic<bool> too_many{false};

  // The sorted points' coordinates as separate arrays: a cell's candidates are then copied
  // range by range with wide loads instead of picked out of each point one float at a time
  // (that transposition was most of this function's own time).
  // Padded with far points: the candidate gathering reads whole groups past a range's end.
  constexpr float kFar = std::numeric_limits<float>::infinity();
  soa_x_.resize(n + kCandidatePadding);
  soa_y_.resize(n + kCandidatePadding);
  soa_z_.resize(n + kCandidatePadding);
  float *const sx = soa_x_.data(), *const sy = soa_y_.data(), *const sz = soa_z_.data();
  std::fill(sx + n, sx + n + kCandidatePadding, kFar);
  std::fill(sy + n, sy + n + kCandidatePadding, kFar);
  std::fill(sz + n, sz + n + kCandidatePadding, kFar);
  // The gathering keeps points within the radius of the box around a cell's points, a margin
  // wider than the radius: its test is exact in itself, and the margin keeps it so should the
  // compiler fuse a multiply-add in one of the two tests and not in the other.
  const float r2_near_box = r2 * (1.0f + 1e-5f);

#pragma omp parallel
  {
    const int t = omp_get_thread_num();
    const int nt = omp_get_num_threads();
#pragma omp single
    {
      scratch.resize(nt);
      thread_filled_.assign(nt, 0);
      block_base.assign(nt + 1, 0);
    }
#pragma omp for schedule(static)
    for (std::size_t j = 0; j < n; ++j) {
      sx[j] = pts[j].x();
      sy[j] = pts[j].y();
      sz[j] = pts[j].z();
    }
    const std::size_t begin = n * t / nt, end = n * (t + 1) / nt;
    auto& buf = scratch[t].list;
    // buf's size is its capacity: growing it by resize() would zero every candidate slot of
    // every particle first (27 cells of candidates, ~40 kept); `used` is the filled part.
    if (buf.size() < (end - begin) * 48) buf.resize((end - begin) * 48);
    std::size_t used = 0;
    // All particles of a cell share their candidate set: the points of the 27 cells around
    // it that lie within the radius of the box around the cell's particles (about a third of
    // them at h = 2d, where that box is half a cell wide). It is gathered once per cell into
    // a contiguous local copy (ascending index), then every particle of the cell is tested
    // against it (CandidateFilter.h: eight candidates at a time where the CPU can).
    std::vector<std::uint32_t>& cand = scratch[t].candidates;
    std::vector<float>&cx = scratch[t].x, &cy = scratch[t].y, &cz = scratch[t].z;
    std::size_t i = begin;
    while (i < end && !too_many.load(std::memory_order_relaxed)) {
      const std::uint32_t dense = point_cell_[i];
      std::size_t cell_end = i + 1;
      while (cell_end < end && point_cell_[cell_end] == dense) ++cell_end;
      const int x0 = dense % nx, y0 = (dense / nx) % ny, z0 = dense / (nx * ny);
      Range ranges[27];
      int range_count = 0;
      for (int z = std::max(z0 - 1, 0); z <= std::min(z0 + 1, nz - 1); ++z)
        for (int y = std::max(y0 - 1, 0); y <= std::min(y0 + 1, ny - 1); ++y)
          for (int x = std::max(x0 - 1, 0); x <= std::min(x0 + 1, nx - 1); ++x) {
            const std::uint32_t r = rank_[x + nx * (y + ny * z)];
            if (cell_start_[r] != cell_start_[r + 1])
              ranges[range_count++] = {cell_start_[r], cell_start_[r + 1]};
          }
      std::sort(ranges, ranges + range_count,
                [](const Range& a, const Range& b) { return a.begin < b.begin; });
      // Cells next to each other in Morton order are next to each other in memory: one run.
      int runs = 0;
      for (int k = 0; k < range_count; ++k) {
        if (runs > 0 && ranges[runs - 1].end == ranges[k].begin) ranges[runs - 1].end = ranges[k].end;
        else ranges[runs++] = ranges[k];
      }
      range_count = runs;
      std::size_t all = 0;
      for (int k = 0; k < range_count; ++k) all += ranges[k].end - ranges[k].begin;
      // Room for every candidate and a group of the filter's width beyond. The arrays only
      // grow (resizing down and up again would zero them every cell), and are filled through
      // raw pointers: a push_back per candidate stored the vector's end each time.
      const std::size_t room = all + kCandidatePadding;
      if (cand.size() < room) {
        cand.resize(room);
        cx.resize(room);
        cy.resize(room);
        cz.resize(room);
      }
      std::uint32_t* const ci = cand.data();
      float *const px = cx.data(), *const py = cy.data(), *const pz = cz.data();
      float lo[3] = {sx[i], sy[i], sz[i]}, hi[3] = {sx[i], sy[i], sz[i]};
      for (std::size_t p = i + 1; p < cell_end; ++p) {
        lo[0] = std::min(lo[0], sx[p]), hi[0] = std::max(hi[0], sx[p]);
        lo[1] = std::min(lo[1], sy[p]), hi[1] = std::max(hi[1], sy[p]);
        lo[2] = std::min(lo[2], sz[p]), hi[2] = std::max(hi[2], sz[p]);
      }
      const CandidateBuffer out{px, py, pz, ci};
      std::size_t m = 0;
      for (int k = 0; k < range_count; ++k)
        m = appendCandidatesNearBox(sx, sy, sz, ranges[k].begin, ranges[k].end, lo, hi, r2_near_box, out, m);
      // Padded to whole groups of the filter's width with points that are never near.
      const std::size_t padded = (m + kCandidatePadding - 1) / kCandidatePadding * kCandidatePadding;
      for (std::size_t c = m; c < padded; ++c) ci[c] = 0, px[c] = py[c] = pz[c] = kFar;
      const Candidates candidates{px, py, pz, ci, m};
      for (; i < cell_end; ++i) {
        offsets_[i] = static_cast<std::uint32_t>(used);  // block-local until the merge
        // Checked before the buffer grows: in a collapsed fluid one cell holds thousands of
        // points, and its lists alone would take gigabytes before the cell ends.
        if (used + padded > max_pairs) {
          too_many = true;
          break;
        }
        if (buf.size() < used + padded) buf.resize(std::max(2 * buf.size(), used + padded));
        used += keepCandidatesWithin(candidates, pts[i].x(), pts[i].y(), pts[i].z(), r2,
                                     static_cast<std::uint32_t>(i), buf.data() + used);
      }
    }
    thread_filled_[t] = used;
#pragma omp barrier
#pragma omp single
    {
      for (int b = 0; b < nt; ++b) block_base[b + 1] = block_base[b] + thread_filled_[b];
      if (block_base[nt] > max_pairs) too_many = true;
      if (!too_many) {
        indices_.resize(block_base[nt]);
        offsets_[n] = static_cast<std::uint32_t>(block_base[nt]);
      }
    }
    if (!too_many) {
      std::copy(buf.begin(), buf.begin() + thread_filled_[t], indices_.begin() + block_base[t]);
      const auto base = static_cast<std::uint32_t>(block_base[t]);
      for (std::size_t i = begin; i < end; ++i) offsets_[i] += base;
    }
  }
  if (too_many) {
    offsets_.assign(n + 1, 0);  // no lists rather than wrong ones
    indices_.clear();
    throw std::length_error("more than " + std::to_string(max_pairs) + " neighbour pairs for " +
                            std::to_string(n) + " particles (" + std::to_string(max_pairs / std::max<std::size_t>(n, 1)) +
                            " each): they are packed far denser than a fluid");
  }
}

}  // namespace pbf
