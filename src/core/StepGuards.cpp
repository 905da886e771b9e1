#include "pbf_ros/core/PbfSolver.h"

#include <omp.h>

#include <algorithm>
#include <cmath>

#include "DeterministicSum.h"

// Guards that keep a step's result usable (speed cap, finiteness) and its statistics.

namespace pbf {

void PbfSolver::enforceSpeedLimit(float dt, StepStats& stats) {
  const float cap = maxSpeedCap();
  if (cap <= 0.0f) return;
  const float cap2 = cap * cap;
  int limited = 0;
#pragma omp parallel for reduction(+ : limited) schedule(static)
  for (std::size_t i = 0; i < size(); ++i) {
    const float s2 = velocity_[i].squaredNorm();
    if (s2 > cap2) {
      velocity_[i] *= cap / std::sqrt(s2);
      ++limited;
    }
  }
  stats.speed_limited = limited > 0;
}

bool PbfSolver::stateIsFinite() const {
  int bad = 0;
#pragma omp parallel for reduction(+ : bad) schedule(static)
  for (std::size_t i = 0; i < size(); ++i)
    if (!position_[i].allFinite() || !velocity_[i].allFinite() || !std::isfinite(density_[i])) ++bad;
  return bad == 0;
}

void PbfSolver::gatherStats(StepStats& stats) const {
  const std::size_t n = size();
  const double inv_rho0 = 1.0 / params_.rest_density;
  const double mass = params_.particleMass();
  double max_err = n ? -1.0 : 0.0;
  float vmax2 = 0.0f;
#pragma omp parallel for reduction(max : max_err, vmax2) schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    max_err = std::max(max_err, density_[i] * inv_rho0 - 1.0);
    vmax2 = std::max(vmax2, velocity_[i].squaredNorm());
  }
  stats.max_density_error = max_err;
  stats.max_speed = std::sqrt(vmax2);
  const double denom = std::max<std::size_t>(n, 1);
  stats.avg_density_error =
      deterministicSum(n, [&](std::size_t i) { return std::max(0.0, density_[i] * inv_rho0 - 1.0); }) /
      denom;
  stats.kinetic_energy =
      0.5 * mass * deterministicSum(n, [&](std::size_t i) { return double(velocity_[i].squaredNorm()); });
}

}  // namespace pbf
