#include "bench/SurfaceMetrics.h"

#include <algorithm>
#include <cmath>

namespace pbf_bench {

double surgeFront(const std::vector<Eigen::Vector3f>& positions, float spacing,
                  const Eigen::AlignedBox3f& container, double min_fraction) {
  const double x0 = container.min().x();
  const int slabs = std::max(1, static_cast<int>(std::ceil(container.sizes().x() / spacing)));
  std::vector<int> count(slabs, 0);
  for (const auto& p : positions) {
    const int k = std::clamp(static_cast<int>(std::floor((p.x() - x0) / spacing)), 0, slabs - 1);
    ++count[k];
  }
  const double row = std::max(1.0, double(container.sizes().y()) / spacing);
  const double needed = std::max(1.0, min_fraction * row);
  int last = -1, gap = 0;
  for (int k = 0; k < slabs; ++k) {
    if (count[k] >= needed) {
      last = k;
      gap = 0;
    } else if (last >= 0 && ++gap > 1) {
      break;
    } else if (last < 0 && k > 1) {
      break;  // nothing attached to the back wall: no body of fluid there
    }
  }
  return last < 0 ? 0.0 : (last + 1) * static_cast<double>(spacing);
}

double surgeFrontSliding(const std::vector<Eigen::Vector3f>& positions, float spacing,
                         const Eigen::AlignedBox3f& container, double min_fraction) {
  const double x0 = container.min().x();
  std::vector<double> x;
  x.reserve(positions.size());
  for (const auto& p : positions) x.push_back(p.x() - x0);
  std::sort(x.begin(), x.end());
  const double row = std::max(1.0, double(container.sizes().y()) / spacing);
  const std::size_t needed = static_cast<std::size_t>(std::ceil(std::max(1.0, min_fraction * row)));
  // The window (x[k] - spacing, x[k]] ends at particle k. As with the slabs, a body must
  // start within two spacings of the back wall, and qualifying windows may be one spacing
  // apart (one empty slab) at most: ends more than two spacings apart break the body.
  double last = -1.0;
  std::size_t begin = 0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    while (x[begin] <= x[k] - spacing) ++begin;
    if (k + 1 - begin < needed) continue;
    const double limit = last < 0.0 ? 2.0 * spacing : last + 2.0 * spacing;
    if (x[k] > limit) break;
    last = x[k];
  }
  return last < 0.0 ? 0.0 : last + 0.5 * spacing;
}

std::vector<double> heightProfile(const std::vector<Eigen::Vector3f>& positions, float spacing,
                                  const Eigen::AlignedBox3f& container, double bin) {
  const Eigen::Vector3f lo = container.min();
  const int nx = std::max(1, static_cast<int>(std::floor(container.sizes().x() / bin)));
  const double column = 2.0 * spacing;
  const int ny = std::max(1, static_cast<int>(std::floor(container.sizes().y() / column)));
  std::vector<double> top(static_cast<std::size_t>(nx) * ny, -1.0);
  for (const auto& p : positions) {
    const int ix = std::clamp(static_cast<int>((p.x() - lo.x()) / bin), 0, nx - 1);
    const int iy = std::clamp(static_cast<int>((p.y() - lo.y()) / column), 0, ny - 1);
    double& t = top[static_cast<std::size_t>(ix) * ny + iy];
    t = std::max(t, static_cast<double>(p.z() - lo.z()) + 0.5 * spacing);
  }
  std::vector<double> h(nx, 0.0);
  for (int ix = 0; ix < nx; ++ix) {
    double sum = 0.0;
    for (int iy = 0; iy < ny; ++iy) sum += std::max(0.0, top[static_cast<std::size_t>(ix) * ny + iy]);
    h[ix] = sum / ny;
  }
  return h;
}

}  // namespace pbf_bench
