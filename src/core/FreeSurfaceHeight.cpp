// The free surface gauge (Metrics.h): where the particles' colour field falls to one half,
// column by column.
//
// Why not the highest particle of each column plus half a spacing (the gauge until session
// 30): once a resting lattice rearranges, its top layer is rough (particles 0.1 d above and
// below their layer's mean), and a column's highest particle stands about 0.1 d above the
// layer's mean. That read the shipped tank's level 0.42 % too high at d = 0.02 m, 0.24 % at
// 0.0125 m and 0.15 % at 0.00833 m, which looked like a level loss growing with resolution. The
// colour field counts every particle by its volume, so a rough layer reads as its mean.

#include <algorithm>
#include <cmath>
#include <vector>

#include "pbf_ros/core/LatticeBoundary.h"
#include "pbf_ros/core/Metrics.h"

namespace pbf {

namespace {

// The gauge's own smoothing, in spacings: the solver's default support, whatever the
// solver runs with, so that a reading does not depend on a solver parameter.
constexpr double kSupport = 2.0;
// Columns about four spacings wide: sixteen particles per layer, so that one particle more
// or less in a column moves its reading by a sixteenth of a layer; the median takes the rest.
constexpr double kColumnWidth = 4.0;

// A column's colour at height z (in spacings): each particle's volume 1 / latticeKernelSum
// (the calibrated mass over rho0, in d^3) spread over the column's cross-section, w^2 d^2,
// by the kernel's plane integral. `heights` is sorted: only those within the support count.
double colour(const std::vector<double>& heights, double z, double particle_volume, double w) {
  double c = 0.0;
  const auto end = std::upper_bound(heights.begin(), heights.end(), z + kSupport);
  for (auto it = std::lower_bound(heights.begin(), heights.end(), z - kSupport); it != end; ++it)
    c += continuumPlaneIntegral(z - *it, kSupport);
  return c * particle_volume / (w * w);
}

// The highest height (in spacings) where the colour of a column (`heights` sorted, not empty)
// reaches one half: stepped down from above an eighth of a spacing at a time, across gaps
// where no particle is near (a splash above the water), then bisected. NaN if it never does
// (a film thinner than the kernel).
double halfColourHeight(const std::vector<double>& heights, double particle_volume, double w) {
  double above = heights.back() + kSupport;  // the colour is zero here
  for (;;) {
    double z = above - 0.125;
    const auto in_reach = std::lower_bound(heights.begin(), heights.end(), z - kSupport);
    if (in_reach == std::upper_bound(heights.begin(), heights.end(), z + kSupport)) {
      if (in_reach == heights.begin()) return NAN;  // below every particle
      z = *(in_reach - 1) + kSupport;               // across the gap: the next particle's reach
    }
    if (colour(heights, z, particle_volume, w) >= 0.5) {
      double below = z;
      for (int k = 0; k < 40; ++k) {
        const double mid = 0.5 * (below + above);
        (colour(heights, mid, particle_volume, w) >= 0.5 ? below : above) = mid;
      }
      return 0.5 * (below + above);
    }
    above = z;
  }
}

// Where the half-colour height of a resting lattice lies from its surface (its top layer
// plus half a spacing), in spacings: the discrete layers put it 0.146 d below. Subtracted, so
// that the start lattice reads its own level exactly, as its mass is calibrated on it.
double latticeOffset(double particle_volume) {
  const int layers = static_cast<int>(std::ceil(3.0 * kSupport)) + 4;
  std::vector<double> lattice;
  for (int k = layers - 1; k >= 0; --k) lattice.push_back(-(k + 0.5));
  return halfColourHeight(lattice, particle_volume, 1.0);
}

}  // namespace

double freeSurfaceHeight(const std::vector<Eigen::Vector3f>& positions, float spacing,
                         const Eigen::AlignedBox3f& container) {
  // No spacing or no particles: no surface to read (as when no column holds any).
  if (!(spacing > 0.0f) || positions.empty() || container.isEmpty()) return 0.0;
  const double d = spacing;
  const double volume = 1.0 / latticeKernelSum(kSupport);
  const Eigen::Vector3d lo = container.min().cast<double>();
  // Columns about four spacings wide, dividing the floor evenly (their widths in spacings).
  const int nx = std::max(1, static_cast<int>(std::floor(container.sizes().x() / (kColumnWidth * d))));
  const int ny = std::max(1, static_cast<int>(std::floor(container.sizes().y() / (kColumnWidth * d))));
  const double wx = container.sizes().x() / (nx * d), wy = container.sizes().y() / (ny * d);
  std::vector<std::vector<double>> columns(static_cast<std::size_t>(nx) * ny);
  for (const auto& p : positions) {
    const int ix = std::clamp(static_cast<int>((p.x() - lo.x()) / (wx * d)), 0, nx - 1);
    const int iy = std::clamp(static_cast<int>((p.y() - lo.y()) / (wy * d)), 0, ny - 1);
    columns[static_cast<std::size_t>(iy) * nx + ix].push_back((p.z() - lo.z()) / d);
  }
  const double offset = latticeOffset(volume);
  std::vector<double> levels;
  for (int iy = 0; iy < ny; ++iy)
    for (int ix = 0; ix < nx; ++ix) {
      const bool wall = ix == 0 || iy == 0 || ix == nx - 1 || iy == ny - 1;
      auto& heights = columns[static_cast<std::size_t>(iy) * nx + ix];
      if ((wall && nx > 2 && ny > 2) || heights.empty()) continue;
      std::sort(heights.begin(), heights.end());
      const double level = halfColourHeight(heights, volume, std::sqrt(wx * wy));
      if (std::isfinite(level)) levels.push_back((level - offset) * d);
    }
  if (levels.empty()) return 0.0;
  std::nth_element(levels.begin(), levels.begin() + levels.size() / 2, levels.end());
  return levels[levels.size() / 2];
}

}  // namespace pbf
