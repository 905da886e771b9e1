#include "pbf_ros/core/PbfSolver.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "pbf_ros/core/Boundaries.h"
#include "pbf_ros/core/ChebyshevAcceleration.h"

// The Jacobi solve (the seed's): every iteration measures the density and each particle's
// multiplier (the lambda pass), then corrects every particle at once from those (the delta-p
// pass, ConstraintPasses.cpp); optionally warm-started and Chebyshev-accelerated.

namespace pbf {

namespace {

// The warm start applies half of the previous step's summed multiplier, as IISPH starts
// from half the previous pressure (Ihmsen et al. 2014). Not all of it: the unrelaxed Jacobi
// pushes overshoot (neighbours' corrections add up), so their sum exceeds the pressure that
// holds the fluid; applied in full, a resting tank's level rose by 17-19 % even with the
// projected solve that takes over-pushes back (ConstraintPasses.cpp), because within the
// tolerance the surplus still becomes velocity (doc/calibration.md, warm start).
constexpr float kWarmStartFraction = 0.5f;

}  // namespace

// With a tolerance, the error measured by the lambda pass decides whether another correction
// is needed; the last pass is not wasted (ended_on_lambda_pass: it measured the density at
// the final positions).
bool PbfSolver::solveJacobi(float dt, StepStats& stats, bool& ended_on_lambda_pass) {
  const bool use_tolerance = params_.density_tolerance > 0.0f;
  int iter = 0;
  stats.warm_started = prepareWarmStart(dt);
  // Not while the solids' wrenches are measured: the extrapolation moves fluid against the
  // solids (and projects it off them) without the solids feeling it, and floating bodies
  // then gained energy (pbf_stress, raft and buoy: 8 J where 0.06 J is allowed).
  chebyshev_->begin(predicted_, track_wrenches_ ? 0.0f : params_.chebyshev_rho);
  float previous_error = std::numeric_limits<float>::infinity();
  while (iter < params_.max_iterations) {
    // With a warm start the first correction applies the previous step's pressure with this
    // step's gradients: the one correction a Jacobi step cannot make itself, because it
    // spreads only one neighbourhood per iteration (a column's hydrostatic pressure takes many).
    const LambdaPass pass =
        iter == 0 && stats.warm_started ? LambdaPass::kWarmStart : LambdaPass::kNewton;
    float avg_error = 0.0f;
    computeLambdas(avg_error, pass);
    if (!std::isfinite(avg_error)) return false;
    if (iter == 0) stats.initial_density_error = avg_error;
    if (pass == LambdaPass::kNewton && avg_error > previous_error) chebyshev_->restart();
    previous_error = avg_error;
    if (pass == LambdaPass::kNewton && use_tolerance && iter >= params_.minIterations() &&
        avg_error <= params_.density_tolerance) {
      ended_on_lambda_pass = true;
      break;
    }
    correctPositions(pass);
    if (chebyshev_->isOn()) chebyshev_->extrapolate(predicted_, boundaries());
    ++iter;
    try {
      keepListsValidFor(predicted_, stats);
    } catch (const std::length_error&) {
      return false;
    }
  }
  chebyshev_->end();
  stats.iterations = iter;
  stats.iteration_cap_reached = use_tolerance && !ended_on_lambda_pass;
  return true;
}

bool PbfSolver::prepareWarmStart(float dt) {
  const bool warm = params_.warm_start && lambda_sum_dt_ > 0.0f && params_.max_iterations > 0;
  if (!warm) {
    std::fill(lambda_sum_.begin(), lambda_sum_.end(), 0.0f);
    return false;
  }
  // lambda is a position-level multiplier: the pressure it stands for is lambda / dt^2.
  const float ratio = dt / lambda_sum_dt_;
  const float scale = kWarmStartFraction * ratio * ratio;
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < lambda_sum_.size(); ++i) lambda_sum_[i] *= scale;
  return true;
}

}  // namespace pbf
