#include "pbf_ros/core/LatticeBoundary.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <mutex>
#include <stdexcept>

namespace pbf {

namespace {

// Table resolution: 8 nodes per spacing puts every lattice position (d/2 + k d) on a node,
// so a resting lattice is looked up exactly; in between, trilinear interpolation of a
// function that varies on the scale of d stays within ~0.1 % of rho0.
constexpr int kNodesPerSpacing = 8;

// The density kernel (Spiky, Kernels.h) in units of d: W(r) = c (H - r)^3, H = h/d, and
// its derivative factor.
struct UnitSpiky {
  explicit UnitSpiky(double factor) : H(factor), c(15.0 / (M_PI * std::pow(factor, 6.0))) {}
  double value(double r2) const {
    const double u = H - std::sqrt(r2);
    return u > 0.0 ? c * u * u * u : 0.0;
  }
  // dW/dx = -3 c (H - r)^2 x / r: returns -3 c (H - r)^2 / r, to be multiplied by x. Zero
  // at r = 0, where the cusp has no direction (as for coincident particles).
  double gradientFactor(double r2) const {
    const double r = std::sqrt(r2);
    const double u = H - r;
    return u > 0.0 && r > 0.0 ? -3.0 * c * u * u / r : 0.0;
  }
  double H, c;
};

// Lattice offsets along one axis that lie beyond a plane at distance a (units of d):
// a + 1/2 + k for k >= 0, within the support.
std::vector<double> ghostOffsets(double a, double factor) {
  std::vector<double> out;
  for (double o = a + 0.5; o < factor; o += 1.0)
    if (o > -factor) out.push_back(o);
  return out;
}

// Integral of the polynomial sum_n p[n] r^n from lo to hi.
template <std::size_t N>
double integratePolynomial(const std::array<double, N>& p, double lo, double hi) {
  double total = 0.0, lo_pow = lo, hi_pow = hi;
  for (std::size_t n = 0; n < N; ++n) {
    total += p[n] * (hi_pow - lo_pow) / static_cast<double>(n + 1);
    lo_pow *= lo;
    hi_pow *= hi;
  }
  return total;
}

template <std::size_t A, std::size_t B>
std::array<double, A + B - 1> multiply(const std::array<double, A>& a, const std::array<double, B>& b) {
  std::array<double, A + B - 1> out{};
  for (std::size_t i = 0; i < A; ++i)
    for (std::size_t j = 0; j < B; ++j) out[i + j] += a[i] * b[j];
  return out;
}

// The table only depends on h/d: build it once per factor and share it.
std::vector<Eigen::Vector4f> buildTable(double factor, double full_line, double step, int nodes) {
  const UnitSpiky w(factor);
  const double norm = 1.0 / latticeKernelSum(factor);
  std::vector<std::vector<double>> offsets(nodes);
  for (int i = 0; i < nodes; ++i) offsets[i] = ghostOffsets(full_line + i * step, factor);
  std::vector<Eigen::Vector4f> table(static_cast<std::size_t>(nodes) * nodes * nodes);
#pragma omp parallel for schedule(static)
  for (int k = 0; k < nodes; ++k)
    for (int j = 0; j < nodes; ++j)
      for (int i = 0; i < nodes; ++i) {
        double t = 0.0, ta = 0.0, tb = 0.0, tc = 0.0;
        for (double z : offsets[k])
          for (double y : offsets[j])
            for (double x : offsets[i]) {
              const double r2 = x * x + y * y + z * z;
              const double g = w.gradientFactor(r2);
              t += w.value(r2);
              ta += g * x;
              tb += g * y;
              tc += g * z;
            }
        table[(static_cast<std::size_t>(k) * nodes + j) * nodes + i] =
            Eigen::Vector4f(t * norm, ta * norm, tb * norm, tc * norm);
      }
  return table;
}

}  // namespace

double latticeKernelSum(double support_radius_factor) {
  const UnitSpiky w(support_radius_factor);
  const int n = static_cast<int>(std::ceil(support_radius_factor));
  double sum = 0.0;
  for (int z = -n; z <= n; ++z)
    for (int y = -n; y <= n; ++y)
      for (int x = -n; x <= n; ++x) sum += w.value(double(x * x + y * y + z * z));
  return sum;
}

double latticeJacobiAmplification(double support_radius_factor) {
  static std::mutex cache_mutex;
  static std::map<double, double> cache;
  const std::lock_guard<std::mutex> lock(cache_mutex);
  auto found = cache.find(support_radius_factor);
  if (found != cache.end()) return found->second;
  // dC_0/dx_p = (m / rho0) grad_p W(x_0 - x_p) = -(m / rho0) grad W(x_0 - x_p) for p != 0;
  // the mass and the sign cancel in the ratio. On the lattice dC_0/dx_0 = 0 (symmetry).
  const UnitSpiky w(support_radius_factor);
  const int n = static_cast<int>(std::ceil(support_radius_factor));
  std::vector<std::array<double, 6>> terms;  // offset, gradient
  double diagonal = 0.0;
  for (int z = -n; z <= n; ++z)
    for (int y = -n; y <= n; ++y)
      for (int x = -n; x <= n; ++x) {
        const double r2 = double(x * x + y * y + z * z);
        const double f = w.gradientFactor(r2);
        if (f == 0.0) continue;
        terms.push_back({double(x), double(y), double(z), f * x, f * y, f * z});
        diagonal += f * f * r2;
      }
  constexpr int kSteps = 16;
  double largest = 0.0;
  for (int a = 0; a <= kSteps; ++a)
    for (int b = 0; b <= kSteps; ++b)
      for (int c = 0; c <= kSteps; ++c) {
        const double kx = M_PI * a / kSteps, ky = M_PI * b / kSteps, kz = M_PI * c / kSteps;
        double re[3] = {0.0, 0.0, 0.0}, im[3] = {0.0, 0.0, 0.0};
        for (const auto& t : terms) {
          const double phase = kx * t[0] + ky * t[1] + kz * t[2];
          const double cs = std::cos(phase), sn = std::sin(phase);
          for (int d = 0; d < 3; ++d) re[d] += t[3 + d] * cs, im[d] -= t[3 + d] * sn;
        }
        double g2 = 0.0;
        for (int d = 0; d < 3; ++d) g2 += re[d] * re[d] + im[d] * im[d];
        largest = std::max(largest, g2);
      }
  const double amplification = diagonal > 0.0 ? largest / diagonal : 0.0;
  cache.emplace(support_radius_factor, amplification);
  return amplification;
}

double latticeGradientScale(double support_radius_factor) {
  // Gradient magnitude of the density kernel in units of d: 45 / (pi H^6) (H - r)^2, times m/rho0.
  const double H = support_radius_factor;
  const double coef = 45.0 / (M_PI * std::pow(H, 6.0)) / latticeKernelSum(H);
  const int n = static_cast<int>(std::ceil(H));
  double sum = 0.0;
  for (int z = -n; z <= n; ++z)
    for (int y = -n; y <= n; ++y)
      for (int x = -n; x <= n; ++x) {
        const double r = std::sqrt(double(x * x + y * y + z * z));
        if (r <= 0.0 || r >= H) continue;
        const double g = coef * (H - r) * (H - r);
        sum += g * g;
      }
  return sum;
}

LatticeBoundary::LatticeBoundary(float spacing, float support_radius)
    : d_(spacing), h_(support_radius) {
  if (!(spacing > 0.0f) || !(support_radius > spacing * 0.5f))
    throw std::invalid_argument("LatticeBoundary: need spacing > 0 and support radius > d/2");
  const double factor = support_radius / spacing;
  // Below full_line every lattice point of the axis within the support is included, with
  // the lattice aligned to the particle (offsets are whole multiples of d).
  full_line_ = -(std::ceil(factor) + 0.5f);
  reach_ = static_cast<float>(factor) - 0.5f;  // the nearest ghost layer leaves the support
  step_ = 1.0f / kNodesPerSpacing;
  nodes_ = static_cast<int>(std::ceil((reach_ - full_line_) / step_)) + 1;

  static std::mutex cache_mutex;
  static std::map<std::pair<float, int>, std::shared_ptr<const std::vector<Eigen::Vector4f>>> cache;
  const std::lock_guard<std::mutex> lock(cache_mutex);
  auto& cached = cache[{static_cast<float>(factor), nodes_}];
  if (!cached)
    cached = std::make_shared<const std::vector<Eigen::Vector4f>>(
        buildTable(factor, full_line_, step_, nodes_));
  table_ = cached;
}

bool LatticeBoundary::octant(const Eigen::Vector3f& s, float& value, Eigen::Vector3f& d_ds) const {
  value = 0.0f;
  d_ds.setZero();
  const float inv_d = 1.0f / d_;
  int idx[3];
  float frac[3];
  for (int a = 0; a < 3; ++a) {
    const float u = s[a] * inv_d;
    if (u >= reach_) return false;
    const float t = (std::max(u, full_line_) - full_line_) / step_;
    const int i = std::min(static_cast<int>(t), nodes_ - 2);
    idx[a] = i;
    frac[a] = t - static_cast<float>(i);
  }
  Eigen::Vector4f acc = Eigen::Vector4f::Zero();
  for (int corner = 0; corner < 8; ++corner) {
    float weight = 1.0f;
    std::size_t flat = 0;
    for (int a = 2; a >= 0; --a) {
      const int bit = (corner >> a) & 1;
      weight *= bit ? frac[a] : 1.0f - frac[a];
      flat = flat * nodes_ + idx[a] + bit;
    }
    acc += weight * (*table_)[flat];
  }
  value = acc[0];
  d_ds = acc.tail<3>() * inv_d;
  // Clamped arguments take the whole line: the table is flat there.
  for (int a = 0; a < 3; ++a)
    if (s[a] * inv_d <= full_line_) d_ds[a] = 0.0f;
  return true;
}

float LatticeBoundary::halfSpace(float s, float& d_ds) const {
  float value = 0.0f;
  Eigen::Vector3f g;
  const float full = fullLine();
  octant(Eigen::Vector3f(s, full, full), value, g);
  d_ds = g[0];
  return value;
}

// The Spiky kernel as a polynomial in r, and its coefficient, for support h.
std::array<double, 4> spikyPolynomial(double h) { return {h * h * h, -3 * h * h, 3 * h, -1}; }
double spikyCoefficient(double h) { return 15.0 / (M_PI * std::pow(h, 6.0)); }

double continuumHalfSpaceFraction(double s, double h) {
  if (s >= h) return 0.0;
  if (s < 0.0) return 1.0 - continuumHalfSpaceFraction(-s, h);
  // Shells of radius r > s: the part beyond the plane is a cap of area 2 pi r (r - s).
  const std::array<double, 3> cap = {0, -s, 1};
  return 2.0 * M_PI * spikyCoefficient(h) * integratePolynomial(multiply(spikyPolynomial(h), cap), s, h);
}

double continuumPlaneIntegral(double s, double h) {
  s = std::abs(s);
  if (s >= h) return 0.0;
  // Shells of radius r > s cut the plane in a circle: the area element is 2 pi r dr.
  const std::array<double, 2> circle = {0, 1};
  return 2.0 * M_PI * spikyCoefficient(h) * integratePolynomial(multiply(spikyPolynomial(h), circle), s, h);
}

double continuumBallFraction(double s, double radius, double h) {
  if (s >= h) return 0.0;
  // Shells of radius r around the particle: the part of each shell inside the ball is a
  // spherical cap of area 2 pi r^2 (1 - cos alpha), cos alpha = (D^2 + r^2 - R^2) / (2 D r),
  // D = R + s. With W = c (h - r)^3 the integrand is a polynomial in r.
  const double D = radius + s, R = radius;
  const double hi = std::min(h, D + R), lo = std::max(s, 0.0);
  if (hi <= lo) return 0.0;
  const std::array<double, 4> cap = {0, -(D * D - R * R) / (2 * D), 1, -1 / (2 * D)};
  return 2.0 * M_PI * spikyCoefficient(h) * integratePolynomial(multiply(spikyPolynomial(h), cap), lo, hi);
}

}  // namespace pbf
