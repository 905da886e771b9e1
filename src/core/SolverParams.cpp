#include "pbf_ros/core/SolverParams.h"

#include "pbf_ros/core/LatticeBoundary.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace pbf {

namespace {
bool finite(float v) { return std::isfinite(v); }
}  // namespace

float SolverParams::particleMass() const {
  const double d = particle_spacing;
  return static_cast<float>(rest_density * d * d * d);
}

float SolverParams::densityMass() const {
  return static_cast<float>(particleMass() / latticeKernelSum(support_radius_factor));
}

float SolverParams::overlapRelaxation() const {
  constexpr double kValidatedFactor = 2.0;
  const double ratio =
      latticeJacobiAmplification(kValidatedFactor) / latticeJacobiAmplification(support_radius_factor);
  return static_cast<float>(std::min(1.0, ratio));
}

float SolverParams::cfmEpsilon() const {
  const double d = particle_spacing;
  return static_cast<float>(cfm_relaxation * latticeGradientScale(support_radius_factor) / (d * d));
}

float SolverParams::xsphCoefficient(float dt) const {
  const float h = supportRadius();
  return std::min(22.0f * xsph_viscosity * dt / (h * h), 0.5f);
}

std::string SolverParams::validate() const {
  std::ostringstream err;
  auto positive = [&](const char* name, float v) {
    if (!(finite(v) && v > 0.0f)) err << name << " must be a finite number > 0 (got " << v << ")";
  };
  auto nonNegative = [&](const char* name, float v) {
    if (!(finite(v) && v >= 0.0f)) err << name << " must be a finite number >= 0 (got " << v << ")";
  };
  positive("rest_density", rest_density);
  if (err.tellp() == 0) positive("particle_spacing", particle_spacing);
  if (err.tellp() == 0 && !(finite(support_radius_factor) && support_radius_factor >= 1.0f &&
                            support_radius_factor <= 4.0f))
    err << "support_radius_factor must be in [1, 4] (got " << support_radius_factor << ")";
  if (err.tellp() == 0 && !gravity.allFinite()) err << "gravity must be finite";
  if (err.tellp() == 0) positive("time_step", time_step);
  if (err.tellp() == 0) positive("cfl_factor", cfl_factor);
  if (err.tellp() == 0) positive("min_time_step", min_time_step);
  if (err.tellp() == 0) positive("max_time_step", max_time_step);
  if (err.tellp() == 0 && min_time_step > max_time_step)
    err << "min_time_step (" << min_time_step << ") must be <= max_time_step (" << max_time_step
        << ")";
  if (err.tellp() == 0 && (min_iterations < 0 || max_iterations < minIterations() ||
                           max_iterations > 1000))
  {
    err << "iterations must satisfy 0 <= min_iterations <= max_iterations <= 1000 (got min_iterations "
        << min_iterations << ", max_iterations " << max_iterations;
    if (min_iterations == 0)
      err << "; min_iterations 0 means " << minIterations() << " for the "
          << (gauss_seidel ? "Gauss-Seidel" : "Jacobi") << " solve: set it too for fewer";
    err << ")";
  }
  if (err.tellp() == 0) nonNegative("density_tolerance", density_tolerance);
  if (err.tellp() == 0) nonNegative("cfm_relaxation", cfm_relaxation);
  if (err.tellp() == 0 && !(finite(chebyshev_rho) && chebyshev_rho >= 0.0f && chebyshev_rho <= 0.99f))
    err << "chebyshev_rho must be in [0, 0.99] (0: off; got " << chebyshev_rho << ")";
  if (err.tellp() == 0) nonNegative("scorr_k", scorr_k);
  if (err.tellp() == 0 && !(finite(gauss_seidel_omega) && gauss_seidel_omega > 0.0f && gauss_seidel_omega < 2.0f))
    err << "gauss_seidel_omega must be in (0, 2) (1: plain Gauss-Seidel; got " << gauss_seidel_omega << ")";
  if (err.tellp() == 0 && gauss_seidel && (warm_start || chebyshev_rho > 0.0f || scorr_k > 0.0f))
    err << "gauss_seidel replaces the Jacobi solve that warm_start, chebyshev_rho and scorr_k act on: "
        << "turn those off to use it (got warm_start " << (warm_start ? "true" : "false")
        << ", chebyshev_rho " << chebyshev_rho << ", scorr_k " << scorr_k << ")";
  // The warm start re-applies the last step's multipliers before the solve sees this step's
  // positions; its solve then keeps each particle's sum <= 0 (projectedSolve), taking back
  // what over-pushed. A two-sided constraint's pulls have no such bound: warm-started, the
  // dam break ran to the speed cap within 0.2 s (40 000 J), or its steps failed at every dt.
  if (err.tellp() == 0 && warm_start && !unilateral_constraint)
    err << "warm_start needs the one-sided constraint (unilateral_constraint true): its solve "
        << "bounds each particle's summed multiplier, which a two-sided constraint's pulls do not allow";
  if (err.tellp() == 0 && !(finite(scorr_n) && scorr_n >= 1.0f && scorr_n <= 16.0f))
    err << "scorr_n must be in [1, 16] (got " << scorr_n << ")";
  // Beyond the rest spacing d = h / support_radius_factor, s_corr pushes a fluid at rest
  // apart harder than k: with k = 1 a dam break gained 8 times its potential energy in 0.1 s
  // at 0.6 h, and ran as without s_corr at 0.5 h (h = 2d).
  if (err.tellp() == 0 && !(finite(scorr_delta_q) && scorr_delta_q > 0.0f &&
                            scorr_delta_q <= 1.0f / support_radius_factor))
    err << "scorr_delta_q must be in (0, " << 1.0f / support_radius_factor
        << "] (a fraction of h, at most the rest spacing d = h / support_radius_factor: beyond, "
        << "s_corr pushes water at rest apart; got " << scorr_delta_q << ")";
  if (err.tellp() == 0 && !(finite(xsph_viscosity) && xsph_viscosity >= 0.0f && xsph_viscosity <= 1.0f))
    err << "xsph_viscosity must be in [0, 1] m^2/s (got " << xsph_viscosity << ")";
  if (err.tellp() == 0 && !(finite(vorticity_epsilon) && vorticity_epsilon >= 0.0f &&
                            vorticity_epsilon <= kMaxVorticityEpsilon))
    err << "vorticity_epsilon must be in [0, " << kMaxVorticityEpsilon
        << "] 1/s (beyond, confinement outgrows the fluid's damping and stirs water at rest; got "
        << vorticity_epsilon << ")";
  if (err.tellp() == 0 && !(finite(wall_friction) && wall_friction >= 0.0f && wall_friction <= 10.0f))
    err << "wall_friction must be in [0, 10] (a friction coefficient; got " << wall_friction << ")";
  if (err.tellp() == 0 && !(finite(neighbor_skin) && neighbor_skin >= 0.0f && neighbor_skin <= 1.0f))
    err << "neighbor_skin must be in [0, 1] (fraction of h; got " << neighbor_skin << ")";
  if (err.tellp() == 0 && (max_nan_retries < 0 || max_nan_retries > 30))
    err << "max_nan_retries must be in [0, 30] (got " << max_nan_retries << ")";
  if (err.tellp() == 0) nonNegative("max_speed_factor", max_speed_factor);
  return err.str();
}

float SolverParams::speedCap(float longest_side) const {
  if (max_speed_factor <= 0.0f || !(longest_side > 0.0f)) return 0.0f;
  const float g = std::max(gravity.norm(), 9.81f);
  return max_speed_factor * std::sqrt(2.0f * g * longest_side);
}

}  // namespace pbf
