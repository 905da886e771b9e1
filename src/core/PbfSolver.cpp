#include "pbf_ros/core/PbfSolver.h"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "BlockColours.h"
#include "FreeSurfaceLend.h"
#include "PackedSlots.h"
#include "pbf_ros/core/Boundaries.h"
#include "pbf_ros/core/ChebyshevAcceleration.h"
#include "pbf_ros/core/LatticeBoundary.h"
#include "pbf_ros/core/NeighborGrid.h"

namespace pbf {

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

}  // namespace

PbfSolver::PbfSolver()
    : grid_(std::make_unique<NeighborGrid>()),
      colours_(std::make_unique<BlockColours>()),
      chebyshev_(std::make_unique<ChebyshevAcceleration>()),
      lattice_(std::make_unique<LatticeBoundary>(params_.particle_spacing, params_.supportRadius())),
      packed_(std::make_unique<PackedSlots>()) {}
PbfSolver::~PbfSolver() = default;

void PbfSolver::setParams(const SolverParams& params) {
  const std::string err = params.validate();
  if (!err.empty()) throw std::invalid_argument("solver parameter: " + err);
  const bool radius_changed = params.supportRadius() != params_.supportRadius() ||
                              params.neighbor_skin != params_.neighbor_skin;
  // The kept multipliers carry the constraint's units (m^2 through m / rho0 and h): they
  // mean nothing for another mass, spacing or kernel.
  const bool constraint_scale_changed = radius_changed ||
                                        params.densityMass() != params_.densityMass() ||
                                        params.rest_density != params_.rest_density;
  // The free surface's lend table, built before anything changes (it is calibrated for one
  // spacing and kernel: the particles' lends are then measured afresh).
  const bool new_lend_table = params.free_surface_lend &&
                              (!surface_lend_table_ || surface_lend_table_->spacing() != params.particle_spacing ||
                               surface_lend_table_->supportRadius() != params.supportRadius());
  auto lend_table = new_lend_table
                        ? std::make_unique<FreeSurfaceLend>(params.particle_spacing, params.supportRadius())
                        : nullptr;
  params_ = params;
  overlap_relaxation_ = params_.overlapRelaxation();
  if (radius_changed) lists_valid_ = false;
  if (constraint_scale_changed) lambda_sum_dt_ = 0.0f;
  if (!params_.free_surface_lend) {
    surface_lend_table_.reset();
  } else if (new_lend_table) {
    surface_lend_table_ = std::move(lend_table);
    std::fill(surface_lend_.begin(), surface_lend_.end(), FreeSurfaceLend::kUnmeasured);
  }
  if (lattice_->spacing() != params_.particle_spacing ||
      lattice_->supportRadius() != params_.supportRadius())
    lattice_ = std::make_unique<LatticeBoundary>(params_.particle_spacing, params_.supportRadius());
}

void PbfSolver::setContainer(const Eigen::AlignedBox3f& box) {
  if (!box.isEmpty() && !(box.min().allFinite() && box.max().allFinite()))
    throw std::invalid_argument("container: corners must be finite");
  container_ = box;
}

void PbfSolver::setContainerPose(const Eigen::Isometry3f& pose) {
  if (!pose.matrix().allFinite()) throw std::invalid_argument("container pose must be finite");
  container_pose_ = pose;
}

void PbfSolver::setObstacles(const std::vector<Obstacle>& obstacles) {
  for (std::size_t k = 0; k < obstacles.size(); ++k) {
    const std::string err = obstacles[k].validate();
    if (!err.empty()) throw std::invalid_argument("obstacle " + std::to_string(k) + ": " + err);
  }
  obstacles_ = obstacles;
  prev_obstacle_pose_.clear();
  for (const auto& o : obstacles_) prev_obstacle_pose_.push_back(o.pose);
}

void PbfSolver::setObstaclePose(std::size_t index, const Eigen::Isometry3f& pose) {
  if (index >= obstacles_.size())
    throw std::invalid_argument("obstacle index " + std::to_string(index) + " out of range");
  if (!pose.matrix().allFinite()) throw std::invalid_argument("obstacle pose must be finite");
  obstacles_[index].pose = pose;
}

void PbfSolver::setParticles(const std::vector<Eigen::Vector3f>& positions,
                             const std::vector<Eigen::Vector3f>& velocities) {
  if (!velocities.empty() && velocities.size() != positions.size())
    throw std::invalid_argument("setParticles: velocities must be empty or match positions (" +
                                std::to_string(velocities.size()) + " vs " +
                                std::to_string(positions.size()) + ")");
  for (std::size_t i = 0; i < positions.size(); ++i)
    if (!positions[i].allFinite() || (!velocities.empty() && !velocities[i].allFinite()))
      throw std::invalid_argument("setParticles: particle " + std::to_string(i) +
                                  " has a non-finite position or velocity");
  const std::size_t n = positions.size();
  position_ = positions;
  velocity_ = velocities.empty() ? std::vector<Eigen::Vector3f>(n, Eigen::Vector3f::Zero())
                                 : velocities;
  id_.resize(n);
  for (std::size_t i = 0; i < n; ++i) id_[i] = static_cast<std::uint32_t>(i);
  next_id_ = static_cast<std::uint32_t>(n);
  predicted_.assign(n, Eigen::Vector3f::Zero());
  delta_.assign(n, Eigen::Vector3f::Zero());
  new_velocity_.assign(n, Eigen::Vector3f::Zero());
  lambda_.assign(n, 0.0f);
  lambda_sum_.assign(n, 0.0f);
  lambda_sum_dt_ = 0.0f;  // no pressure yet to start from
  surface_lend_.assign(n, FreeSurfaceLend::kUnmeasured);
  density_.assign(n, params_.rest_density);
  neighbor_count_.assign(n, 0);
  lists_valid_ = false;
  time_ = 0.0;
  step_count_ = 0;
}

float PbfSolver::maxSpeedCap() const {
  if (container_.isEmpty()) return 0.0f;
  return params_.speedCap(container_.sizes().maxCoeff());
}

float PbfSolver::nextTimeStep() const {
  if (!params_.adaptive_time_step) return params_.time_step;
  float vmax2 = 0.0f;
#pragma omp parallel for reduction(max : vmax2) schedule(static)
  for (std::size_t i = 0; i < velocity_.size(); ++i) vmax2 = std::max(vmax2, velocity_[i].squaredNorm());
  // Gravity adds up to |g| dt within the step; include it so a resting fluid that starts
  // to fall does not take one over-long step.
  const float vmax = std::sqrt(vmax2) + params_.gravity.norm() * params_.max_time_step;
  float dt = params_.max_time_step;
  if (vmax > 0.0f) dt = params_.cfl_factor * params_.particle_spacing / vmax;
  return std::clamp(dt, params_.min_time_step, params_.max_time_step);
}

StepStats PbfSolver::step() { return stepWith(nextTimeStep()); }

StepStats PbfSolver::stepWith(float dt) {
  const auto t0 = Clock::now();
  StepStats stats;
  stats.particle_count = static_cast<std::uint32_t>(size());
  if (!(std::isfinite(dt) && dt > 0.0f))
    throw std::invalid_argument("step: time step must be finite and > 0");

  saved_position_ = position_;
  saved_velocity_ = velocity_;
  saved_id_ = id_;
  saved_density_ = density_;
  saved_neighbor_count_ = neighbor_count_;
  saved_lambda_sum_ = lambda_sum_;
  saved_surface_lend_ = surface_lend_;
  bool ok = false;
  for (int attempt = 0; attempt <= params_.max_nan_retries; ++attempt) {
    StepStats trial = stats;
    if (attemptStep(dt, trial)) {
      stats = trial;
      ok = true;
      break;
    }
    // Rejected: a non-finite value appeared. Restore and retry with half the step.
    position_ = saved_position_;
    velocity_ = saved_velocity_;
    id_ = saved_id_;
    density_ = saved_density_;
    neighbor_count_ = saved_neighbor_count_;
    lambda_sum_ = saved_lambda_sum_;
    surface_lend_ = saved_surface_lend_;
    lists_valid_ = false;
    ++stats.nan_retries;
    if (attempt_too_dense_) ++stats.dense_retries;
    dt *= 0.5f;
  }
  wrenches_ = SolidWrenches();
  if (!ok) {
    stats.failed = true;
    stats.dt = 0.0;
    gatherStats(stats);
  } else {
    if (track_wrenches_)
      wrenches_ = wrench_sums_.result(params_.particleMass(), stats.dt,
                                      container_pose_.translation().cast<double>(), obstacles_);
    time_ += stats.dt;
    ++step_count_;
    lambda_sum_dt_ = static_cast<float>(stats.dt);
    // The boundaries have now reached the poses set for this step.
    prev_container_pose_ = container_pose_;
    for (std::size_t k = 0; k < obstacles_.size(); ++k) prev_obstacle_pose_[k] = obstacles_[k].pose;
  }
  stats.times.total_ms = msSince(t0);
  stats.times.other_ms = std::max(0.0, stats.times.total_ms - stats.times.neighbors_ms -
                                           stats.times.solve_ms -
                                           stats.times.viscosity_vorticity_ms);
  return stats;
}

std::vector<StepStats> PbfSolver::advance(double duration) {
  std::vector<StepStats> all;
  double remaining = duration;
  while (remaining > 1e-9) {
    // Split what is left evenly instead of ending on a sliver of a step: a tiny dt turns
    // round-off in positions into large velocities.
    const double dt_next = nextTimeStep();
    const double steps = std::ceil(remaining / dt_next - 1e-6);
    const float dt = static_cast<float>(remaining / std::max(1.0, steps));
    all.push_back(stepWith(dt));
    if (all.back().failed) break;
    remaining -= all.back().dt;
  }
  return all;
}

bool PbfSolver::attemptStep(float dt, StepStats& stats) {
  attempt_too_dense_ = false;
  stats.dt = dt;
  current_dt_ = dt;
  surface_lend_set_ = false;  // the solve's first pass updates this step's lend
  if (track_wrenches_)
    wrench_sums_.reset(SolidBoundaries::kContainerFaces + obstacles_.size(), omp_get_max_threads());
  auto t = Clock::now();
  try {
    measureNewLends();  // before gravity moves them (NewParticleLends.cpp)
  } catch (const std::length_error&) {
    return false;  // more neighbour pairs than memory allows: reject, as below
  }
  const bool predicted_finite = predict(dt);
  if (predicted_finite) {
    updateFluidReach();
    // The solve starts inside the solids' bounds, as every later pass sees it: the
    // container's images (ContainerMirror.h) are only right for particles in front of a wall.
    projectOntoSolids();
  }
  stats.times.other_ms += msSince(t);
  if (!predicted_finite) return false;

  t = Clock::now();
  try {
    updateNeighbors(stats);
  } catch (const std::length_error&) {
    return false;  // more neighbour pairs than memory allows: reject, retry with less motion
  }
  stats.times.neighbors_ms += msSince(t);

  t = Clock::now();
  // The constraint iterations, until the density tolerance (or max_iterations).
  bool ended_on_lambda_pass = false;  // the last pass measured the density: see below
  const bool solved = params_.gauss_seidel ? solveGaussSeidel(stats, ended_on_lambda_pass)
                                           : solveJacobi(dt, stats, ended_on_lambda_pass);
  if (!solved) return false;
  stats.grid_cells = grid_->cellCount();
  stats.times.solve_ms += msSince(t);

  t = Clock::now();
  const bool settled_elsewhere = updateVelocities(dt);
  bool reordered = false;
  try {
    reordered = keepListsValidFor(position_, stats);
  } catch (const std::length_error&) {
    return false;
  }
  stats.times.other_ms += msSince(t);

  t = Clock::now();
  // A solve that ended on its tolerance measured the density at the final positions in its
  // last lambda pass: unless something moved or reordered the particles since, the step's
  // density pass would compute it again.
  const bool density_known = ended_on_lambda_pass && !settled_elsewhere && !reordered;
  const float* packed_positions = computeDensityAndVorticity(density_known);
  if (params_.xsph_viscosity > 0.0f || params_.vorticity_epsilon > 0.0f)
    applyViscosityAndVorticity(dt, packed_positions);
  stats.times.viscosity_vorticity_ms += msSince(t);

  t = Clock::now();
  enforceSpeedLimit(dt, stats);
  if (params_.vorticity_epsilon <= 0.0f) stats.skipped_stages.add(SkippedStages::kVorticity);
  if (params_.xsph_viscosity <= 0.0f) stats.skipped_stages.add(SkippedStages::kXsph);
  if (params_.scorr_k <= 0.0f) stats.skipped_stages.add(SkippedStages::kScorr);
  if (stats.neighbor_lists_reused) stats.skipped_stages.add(SkippedStages::kNeighborSearch);
  if (density_known) stats.skipped_stages.add(SkippedStages::kDensityPass);
  if (ended_on_lambda_pass) stats.skipped_stages.add(SkippedStages::kIterationsAfterTolerance);
  const bool finite = stateIsFinite();
  if (finite) gatherStats(stats);
  stats.times.other_ms += msSince(t);
  return finite;
}

bool PbfSolver::predict(float dt) {
  const std::size_t n = size();
  const Eigen::Vector3f dv = dt * params_.gravity;
  int bad = 0;
#pragma omp parallel for reduction(+ : bad) schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    velocity_[i] += dv;
    predicted_[i] = position_[i] + dt * velocity_[i];
    bad += predicted_[i].allFinite() ? 0 : 1;
  }
  return bad == 0;  // an overflow here would poison the grid: reject the attempt now
}

}  // namespace pbf
