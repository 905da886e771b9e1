#include "bench/MartinMoyce.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace pbf_bench {

FrontCurve loadFrontCurve(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open the reference data");
  FrontCurve c;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty() || line[0] == '#' || line.rfind("T,", 0) == 0) continue;
    std::stringstream ss(line);
    double t, z;
    char comma;
    if (!(ss >> t >> comma >> z) || comma != ',')
      throw std::runtime_error(path + ":" + std::to_string(number) + ": expected 'T,Z', got '" + line + "'");
    if (!c.T.empty() && t < c.T.back())
      throw std::runtime_error(path + ":" + std::to_string(number) + ": T must be ascending");
    c.T.push_back(t);
    c.Z.push_back(z);
  }
  if (c.T.size() < 2) throw std::runtime_error(path + ": fewer than 2 data rows");
  return c;
}

double interpolate(const FrontCurve& c, double T) {
  if (c.T.empty()) return 0.0;
  if (T <= c.T.front()) return c.Z.front();
  if (T >= c.T.back()) return c.Z.back();
  const auto it = std::upper_bound(c.T.begin(), c.T.end(), T);
  const std::size_t k = static_cast<std::size_t>(it - c.T.begin());
  const double u = (T - c.T[k - 1]) / std::max(1e-12, c.T[k] - c.T[k - 1]);
  return c.Z[k - 1] + u * (c.Z[k] - c.Z[k - 1]);
}

double frontRms(const FrontCurve& sim, const FrontCurve& ref, double shift, double t_max) {
  double sum = 0.0;
  int n = 0;
  for (std::size_t k = 0; k < ref.T.size(); ++k) {
    if (ref.T[k] > t_max + 1e-9) continue;
    const double e = interpolate(sim, ref.T[k] - shift) - ref.Z[k];
    sum += e * e;
    ++n;
  }
  return n ? std::sqrt(sum / n) : 0.0;
}

double bestShift(const FrontCurve& sim, const FrontCurve& ref, double t_max, double max_shift) {
  double best = 0.0, best_rms = frontRms(sim, ref, 0.0, t_max);
  for (int k = 1; k * 0.01 <= max_shift + 1e-9; ++k) {
    const double rms = frontRms(sim, ref, k * 0.01, t_max);
    if (rms < best_rms) best = k * 0.01, best_rms = rms;
  }
  return best;
}

}  // namespace pbf_bench
