#include "pbf_ros/core/PbfSolver.h"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "pbf_ros/core/Boundaries.h"
#include "pbf_ros/core/Kernels.h"
#include "pbf_ros/core/LatticeBoundary.h"
#include "pbf_ros/core/NeighborGrid.h"

namespace pbf {

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// Sum of f(i) over [0, n) in a fixed association order: chunks of fixed size summed in
// parallel, then the chunk sums in order. Results are bitwise identical for any thread
// count, which keeps tolerance-driven iteration counts independent of the threads.
template <typename F>
double deterministicSum(std::size_t n, F f) {
  constexpr std::size_t kChunk = 2048;
  const std::size_t chunks = (n + kChunk - 1) / kChunk;
  std::vector<double> partial(chunks, 0.0);
#pragma omp parallel for schedule(static)
  for (std::size_t c = 0; c < chunks; ++c) {
    double s = 0.0;
    const std::size_t end = std::min(n, (c + 1) * kChunk);
    for (std::size_t i = c * kChunk; i < end; ++i) s += f(i);
    partial[c] = s;
  }
  double total = 0.0;
  for (double s : partial) total += s;
  return total;
}

// Direction for a pair of coincident particles, which has no geometric direction: a
// pseudo-random unit vector from the pair's ids, antisymmetric (dir(a,b) = -dir(b,a)) so
// momentum is still conserved and coincident particles push apart deterministically.
Eigen::Vector3f coincidentDirection(std::uint32_t id_i, std::uint32_t id_j) {
  const std::uint32_t lo = std::min(id_i, id_j), hi = std::max(id_i, id_j);
  std::uint64_t s = (static_cast<std::uint64_t>(lo) << 32 | hi) * 0x9E3779B97F4A7C15ULL;
  auto next = [&s]() {
    s ^= s >> 31;
    s *= 0xBF58476D1CE4E5B9ULL;
    s ^= s >> 29;
    return static_cast<float>(s >> 40) / static_cast<float>(1 << 24) * 2.0f - 1.0f;
  };
  Eigen::Vector3f d(next(), next(), next());
  if (d.squaredNorm() < 1e-6f) d = Eigen::Vector3f(1, 0, 0);
  d.normalize();
  return id_i < id_j ? d : Eigen::Vector3f(-d);
}

// Pair geometry shared by every pass: r = p_i - p_j, its length, and the Spiky gradient
// grad_i W(r). Coincident pairs get the kernel's finite limit along coincidentDirection.
struct Pair {
  Eigen::Vector3f r;
  float r2;
  float rlen;
};

// s_corr is an artificial pressure, i.e. a force: the displacement it causes must scale
// with dt^2, or a small (CFL) dt turns its fixed push into unbounded speeds (push / dt),
// which shrinks dt further. The paper tuned k at dt = 1/60 s, so that is where the factor
// is 1; it never exceeds 1 (larger steps get no larger push).
constexpr float kScorrReferenceDt = 1.0f / 60.0f;
inline float scorrTimeScale(float dt) {
  const float r = dt / kScorrReferenceDt;
  return std::min(1.0f, r * r);
}

// Largest displacement s_corr may cause in one iteration at the reference dt, as a
// fraction of the spacing.
constexpr float kMaxScorrShift = 0.1f;

// Pairs closer than sqrt(kCoincident) h are treated as coincident.
constexpr float kCoincident = 1e-12f;

inline Eigen::Vector3f spikyGradientSafe(const Kernels& k, const Pair& p, std::uint32_t id_i,
                                         std::uint32_t id_j) {
  if (p.r2 > kCoincident * k.h2) return k.spikyGradient(p.r, p.rlen);
  return (k.spiky_grad_coef * k.h2) * coincidentDirection(id_i, id_j);
}

}  // namespace

PbfSolver::PbfSolver()
    : grid_(std::make_unique<NeighborGrid>()),
      lattice_(std::make_unique<LatticeBoundary>(params_.particle_spacing, params_.supportRadius())) {}
PbfSolver::~PbfSolver() = default;

void PbfSolver::setParams(const SolverParams& params) {
  const std::string err = params.validate();
  if (!err.empty()) throw std::invalid_argument("solver parameter: " + err);
  const bool radius_changed = params.supportRadius() != params_.supportRadius() ||
                              params.neighbor_skin != params_.neighbor_skin;
  params_ = params;
  if (radius_changed) lists_valid_ = false;
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
  predicted_.assign(n, Eigen::Vector3f::Zero());
  delta_.assign(n, Eigen::Vector3f::Zero());
  new_velocity_.assign(n, Eigen::Vector3f::Zero());
  lambda_.assign(n, 0.0f);
  density_.assign(n, params_.rest_density);
  neighbor_count_.assign(n, 0);
  lists_valid_ = false;
  time_ = 0.0;
  step_count_ = 0;
}

float PbfSolver::maxSpeedCap() const {
  if (params_.max_speed_factor <= 0.0f || container_.isEmpty()) return 0.0f;
  const float g = std::max(params_.gravity.norm(), 9.81f);
  const float l = container_.sizes().maxCoeff();
  return params_.max_speed_factor * std::sqrt(2.0f * g * l);
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
    lists_valid_ = false;
    ++stats.nan_retries;
    dt *= 0.5f;
  }
  if (!ok) {
    stats.failed = true;
    stats.dt = 0.0;
    gatherStats(stats);
  } else {
    time_ += stats.dt;
    ++step_count_;
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
  stats.dt = dt;
  current_dt_ = dt;
  auto t = Clock::now();
  const bool predicted_finite = predict(dt);
  stats.times.other_ms += msSince(t);
  if (!predicted_finite) return false;

  t = Clock::now();
  try {
    updateNeighbors(stats);
  } catch (const std::length_error&) {
    return false;  // more neighbour pairs than memory allows: reject, retry with less motion
  }
  stats.times.neighbors_ms += msSince(t);

  // Constraint iterations. With a tolerance, the error measured by the lambda pass
  // decides whether another correction is needed; the last pass is not wasted.
  t = Clock::now();
  const bool use_tolerance = params_.density_tolerance > 0.0f;
  int iter = 0;
  while (iter < params_.max_iterations) {
    float avg_error = 0.0f;
    computeLambdas(avg_error);
    if (!std::isfinite(avg_error)) return false;
    if (iter == 0) stats.initial_density_error = avg_error;
    if (use_tolerance && iter >= params_.min_iterations && avg_error <= params_.density_tolerance)
      break;
    computeDeltas();
    applyDeltasAndBoundary();
    ++iter;
    try {
      keepListsValidFor(predicted_, stats);
    } catch (const std::length_error&) {
      return false;
    }
  }
  stats.iterations = iter;
  stats.grid_cells = grid_->cellCount();
  stats.times.solve_ms += msSince(t);

  t = Clock::now();
  updateVelocities(dt);
  try {
    keepListsValidFor(position_, stats);
  } catch (const std::length_error&) {
    return false;
  }
  stats.times.other_ms += msSince(t);

  t = Clock::now();
  computeDensityAndVorticity();
  if (params_.xsph_viscosity > 0.0f || params_.vorticity_epsilon > 0.0f) applyViscosityAndVorticity(dt);
  stats.times.viscosity_vorticity_ms += msSince(t);

  t = Clock::now();
  enforceSpeedLimit(dt, stats);
  if (params_.vorticity_epsilon <= 0.0f) stats.skipped_stages.push_back("vorticity");
  if (params_.xsph_viscosity <= 0.0f) stats.skipped_stages.push_back("xsph");
  if (params_.scorr_k <= 0.0f) stats.skipped_stages.push_back("scorr");
  if (stats.neighbor_lists_reused) stats.skipped_stages.push_back("neighbor_search");
  if (use_tolerance && stats.iterations < params_.max_iterations)
    stats.skipped_stages.push_back("iterations_after_tolerance");
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

void PbfSolver::reorder(const std::vector<std::uint32_t>& order) {
  const std::size_t n = order.size();
  // Gather into reused scratch arrays and swap: no allocation on the per-step path.
  auto permute = [&](auto& v, auto& scratch) {
    scratch.resize(n);
#pragma omp parallel for schedule(static)
    for (std::size_t k = 0; k < n; ++k) scratch[k] = v[order[k]];
    v.swap(scratch);
  };
  permute(position_, reorder_scratch_);
  permute(velocity_, reorder_scratch_);
  permute(predicted_, reorder_scratch_);
  permute(id_, reorder_id_scratch_);
}

void PbfSolver::updateNeighbors(StepStats& stats) {
  const std::size_t n = size();
  const float h = params_.supportRadius();
  const float skin = params_.neighbor_skin * h;
  if (skin > 0.0f && lists_valid_ && build_position_.size() == n) {
    // Reuse while every particle moved less than half the skin since the build: then no
    // pair closer than h now was farther than h + skin then.
    const float limit2 = 0.25f * skin * skin;
    float moved2 = 0.0f;
#pragma omp parallel for reduction(max : moved2) schedule(static)
    for (std::size_t i = 0; i < n; ++i)
      moved2 = std::max(moved2, (predicted_[i] - build_position_[i]).squaredNorm());
    if (moved2 < limit2) {
      stats.neighbor_lists_reused = true;
      return;
    }
  }
  rebuildNeighborLists(predicted_);
}

void PbfSolver::rebuildNeighborLists(const std::vector<Eigen::Vector3f>& points) {
  // The grid covers the fluid's own bounds, not the whole container: a small fluid in a
  // large container costs what it costs in a small one. Clipped to the container (plus h),
  // where strays outside it share the border cells: one far-away particle must not coarsen
  // the grid for everyone.
  const float radius = params_.supportRadius() * (1.0f + params_.neighbor_skin);
  Eigen::AlignedBox3f domain;
  for (const auto& p : points) domain.extend(p);
  if (!container_.isEmpty()) {
    Eigen::AlignedBox3f walls;
    for (int c = 0; c < 8; ++c)
      walls.extend(container_pose_ * container_.corner(static_cast<Eigen::AlignedBox3f::CornerType>(c)));
    walls.extend(walls.min() - Eigen::Vector3f::Constant(radius)).extend(walls.max() + Eigen::Vector3f::Constant(radius));
    domain = domain.intersection(walls);
  }
  reorder(grid_->build(points, radius, domain));
  grid_->findNeighbors(points, radius);  // `points` is one of the arrays reorder() permuted
  if (params_.neighbor_skin > 0.0f) build_position_ = points;
  lists_valid_ = true;
}

// Reused lists stay exact while every particle is within half the skin of where it was at
// the build: then no pair closer than h now was farther than h + skin then. The solver's
// corrections move particles too, so this is checked after each of them, not only once
// per step; a particle that went too far triggers a rebuild right there.
void PbfSolver::keepListsValidFor(const std::vector<Eigen::Vector3f>& points, StepStats& stats) {
  const float skin = params_.neighbor_skin * params_.supportRadius();
  if (skin <= 0.0f) return;  // built once per step on the predicted positions (the seed)
  const float limit2 = 0.25f * skin * skin;
  float moved2 = 0.0f;
#pragma omp parallel for reduction(max : moved2) schedule(static)
  for (std::size_t i = 0; i < size(); ++i)
    moved2 = std::max(moved2, (points[i] - build_position_[i]).squaredNorm());
  if (moved2 < limit2) return;
  rebuildNeighborLists(points);
  ++stats.neighbor_rebuilds_in_step;
}

// The two hot passes below are written branch-free over raw float arrays so that the
// compiler vectorises the neighbour loop (gathers + masks). Coincident pairs, which have no
// direction, contribute nothing there; they are counted and the rare particle that has one
// is recomputed by the exact scalar path (pairGradient) instead.

Eigen::Vector3f PbfSolver::pairGradient(std::size_t i, std::uint32_t j) const {
  const Kernels k(params_.supportRadius());
  Pair p;
  p.r = predicted_[i] - predicted_[j];
  p.r2 = p.r.squaredNorm();
  if (p.r2 >= k.h2) return Eigen::Vector3f::Zero();
  p.rlen = std::sqrt(p.r2);
  return spikyGradientSafe(k, p, id_[i], id_[j]);
}

void PbfSolver::computeLambdas(float& avg_error) {
  const std::size_t n = size();
  const Kernels k(params_.supportRadius());
  const std::uint32_t* off = grid_->offsets().data();
  const std::uint32_t* nbr = grid_->indices().data();
  const float* P = predicted_.empty() ? nullptr : predicted_[0].data();
  const float mass = params_.particleMass();
  const float inv_rho0 = 1.0f / params_.rest_density;
  const float grad_scale = mass * inv_rho0;  // grad C = (m / rho0) grad W (eq 7 with mass)
  const float self_density = mass * k.poly6(0.0f);
  const bool unilateral = params_.unilateral_constraint;
  const float eps = params_.cfmEpsilon();
  const float h = k.h, h2 = k.h2, poly6c = mass * k.poly6_coef;
  const float spiky = grad_scale * k.spiky_grad_coef;
  const float tiny2 = kCoincident * h2;
  const bool walls = params_.wall_density;
  const SolidBoundaries solids = boundaries();
  // The delta-p pass of this iteration sees the same positions: it reuses each pair's
  // gradient factor instead of another sqrt and division.
  pair_gradient_.resize(grid_->indices().size());
  float* G = pair_gradient_.data();

#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const float xi = P[3 * i], yi = P[3 * i + 1], zi = P[3 * i + 2];
    float rho = self_density, gx = 0.0f, gy = 0.0f, gz = 0.0f, sum_grad2 = 0.0f;
    int coincident = 0;
#pragma omp simd reduction(+ : rho, gx, gy, gz, sum_grad2, coincident)
    for (std::uint32_t e = off[i]; e < off[i + 1]; ++e) {
      const std::uint32_t j = nbr[e];
      const float dx = xi - P[3 * j], dy = yi - P[3 * j + 1], dz = zi - P[3 * j + 2];
      const float r2 = dx * dx + dy * dy + dz * dz;
      const float w = std::max(h2 - r2, 0.0f);
      rho += poly6c * w * w * w;
      const float rlen = std::sqrt(r2);
      const float dl = std::max(h - rlen, 0.0f);
      const float g = r2 > tiny2 ? spiky * dl * dl / rlen : 0.0f;
      G[e] = g;
      coincident += r2 <= tiny2 ? 1 : 0;
      gx += g * dx;
      gy += g * dy;
      gz += g * dz;
      sum_grad2 += g * g * r2;
    }
    if (coincident > 0) {  // rare: redo the gradients with directions for coincident pairs
      Eigen::Vector3f gi = Eigen::Vector3f::Zero();
      sum_grad2 = 0.0f;
      for (std::uint32_t e = off[i]; e < off[i + 1]; ++e) {
        const Eigen::Vector3f g = grad_scale * pairGradient(i, nbr[e]);
        gi += g;
        sum_grad2 += g.squaredNorm();
      }
      gx = gi.x(), gy = gi.y(), gz = gi.z();
    }
    if (walls) {  // solids do not move with the solve: they add to grad_i C only
      float fraction = 0.0f;
      Eigen::Vector3f gw = Eigen::Vector3f::Zero();
      if (solids.density(predicted_[i], fraction, gw)) {
        rho += params_.rest_density * fraction;
        gx += gw.x(), gy += gw.y(), gz += gw.z();
      }
    }
    density_[i] = rho;
    float c = rho * inv_rho0 - 1.0f;
    if (unilateral) c = std::max(c, 0.0f);
    const float denom = sum_grad2 + gx * gx + gy * gy + gz * gz + eps;
    lambda_[i] = c == 0.0f || !(denom > 0.0f) ? 0.0f : -c / denom;
  }
  avg_error = static_cast<float>(
      deterministicSum(n, [&](std::size_t i) {
        return std::max(0.0, static_cast<double>(density_[i]) * inv_rho0 - 1.0);
      }) / std::max<std::size_t>(n, 1));
}

// s_corr = -k (W(r) / W(dq))^n h^2 (Macklin & Mueller eq 13; the seed's eq 11 lost the
// parentheses). It is added to lambda_i + lambda_j, which carry units of m^2 here (with the
// particle mass in grad C); the paper's unit-mass, unit-scale form has no such factor, so
// h^2 makes k dimensionless: the push it causes is the same fraction of h at any resolution.
struct PbfSolver::Scorr {
  Scorr(const SolverParams& p, const Kernels& k, float dt)
      : on(p.scorr_k > 0.0f),
        h2(k.h2),
        poly6_rel(on ? k.poly6_coef / k.poly6(std::pow(p.scorr_delta_q * k.h, 2.0f)) : 0.0f),
        k_scaled(p.scorr_k * k.h2 * scorrTimeScale(dt)),
        n(p.scorr_n),
        n4(p.scorr_n == 4.0f),
        max_shift2(std::pow(kMaxScorrShift * p.particle_spacing * scorrTimeScale(dt), 2.0f)) {}
  // -k (W(r) / W(dq))^n h^2: added to lambda_i + lambda_j of the pair at distance^2 r2.
  float operator()(float r2) const {
    const float w = std::max(h2 - r2, 0.0f);
    const float rel = poly6_rel * w * w * w;
    return -k_scaled * (n4 ? (rel * rel) * (rel * rel) : std::pow(rel, n));
  }
  bool on;
  float h2, poly6_rel, k_scaled, n;
  bool n4;
  float max_shift2;
};

// s_corr is an artificial pressure against clustering: it may nudge a particle by at most
// kMaxScorrShift of the spacing per iteration (at the reference dt). Within that (k up to
// ~1) it acts as Macklin & Mueller describe; beyond, it saturates instead of pumping energy
// into the fluid (the stress suite's s_corr k = 10 case). Each particle gets the factor that
// would bound its own push; a pair then uses the smaller factor of its two particles, so the
// pair's pushes stay equal and opposite (momentum is conserved when the bound acts).
void PbfSolver::computeScorrScales(const Scorr& scorr) {
  const std::size_t n = size();
  const std::uint32_t* off = grid_->offsets().data();
  const std::uint32_t* nbr = grid_->indices().data();
  const float* P = predicted_.empty() ? nullptr : predicted_[0].data();
  const float* G = pair_gradient_.data();
  const float grad_scale = params_.particleMass() / params_.rest_density;
  const float tiny2 = kCoincident * scorr.h2;
  scorr_scale_.resize(n);
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const float xi = P[3 * i], yi = P[3 * i + 1], zi = P[3 * i + 2];
    float sx = 0.0f, sy = 0.0f, sz = 0.0f;
    int coincident = 0;
#pragma omp simd reduction(+ : sx, sy, sz, coincident)
    for (std::uint32_t e = off[i]; e < off[i + 1]; ++e) {
      const std::uint32_t j = nbr[e];
      const float dx = xi - P[3 * j], dy = yi - P[3 * j + 1], dz = zi - P[3 * j + 2];
      const float r2 = dx * dx + dy * dy + dz * dz;
      const float g = scorr(r2) * G[e];
      coincident += r2 <= tiny2 ? 1 : 0;
      sx += g * dx;
      sy += g * dy;
      sz += g * dz;
    }
    Eigen::Vector3f push(sx, sy, sz);
    if (coincident > 0) {  // rare: exact path with directions for coincident pairs
      push.setZero();
      for (std::uint32_t e = off[i]; e < off[i + 1]; ++e) {
        const std::uint32_t j = nbr[e];
        push += scorr((predicted_[i] - predicted_[j]).squaredNorm()) * grad_scale * pairGradient(i, j);
      }
    }
    const float len2 = push.squaredNorm();
    scorr_scale_[i] = len2 > scorr.max_shift2 ? std::sqrt(scorr.max_shift2 / len2) : 1.0f;
  }
}

void PbfSolver::computeDeltas() {
  const std::size_t n = size();
  const Kernels k(params_.supportRadius());
  const std::uint32_t* off = grid_->offsets().data();
  const std::uint32_t* nbr = grid_->indices().data();
  const float* P = predicted_.empty() ? nullptr : predicted_[0].data();
  const float* L = lambda_.data();
  const float* G = pair_gradient_.data();  // (m / rho0) grad W / r, from the lambda pass
  const float grad_scale = params_.particleMass() / params_.rest_density;
  const float tiny2 = kCoincident * k.h2;
  // With k = 0 the loop without s_corr runs: no cost.
  const Scorr scorr(params_, k, current_dt_);
  if (scorr.on) computeScorrScales(scorr);
  const float* S = scorr.on ? scorr_scale_.data() : nullptr;
  const bool walls = params_.wall_density;
  const SolidBoundaries solids = boundaries();

#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const float xi = P[3 * i], yi = P[3 * i + 1], zi = P[3 * i + 2];
    const float li = L[i];
    float dx_sum = 0.0f, dy_sum = 0.0f, dz_sum = 0.0f;
    int coincident = 0;
    if (!scorr.on) {
#pragma omp simd reduction(+ : dx_sum, dy_sum, dz_sum, coincident)
      for (std::uint32_t e = off[i]; e < off[i + 1]; ++e) {
        const std::uint32_t j = nbr[e];
        const float dx = xi - P[3 * j], dy = yi - P[3 * j + 1], dz = zi - P[3 * j + 2];
        const float g = (li + L[j]) * G[e];
        coincident += dx * dx + dy * dy + dz * dz <= tiny2 ? 1 : 0;
        dx_sum += g * dx;
        dy_sum += g * dy;
        dz_sum += g * dz;
      }
    } else {
      const float si = S[i];
#pragma omp simd reduction(+ : dx_sum, dy_sum, dz_sum, coincident)
      for (std::uint32_t e = off[i]; e < off[i + 1]; ++e) {
        const std::uint32_t j = nbr[e];
        const float dx = xi - P[3 * j], dy = yi - P[3 * j + 1], dz = zi - P[3 * j + 2];
        const float r2 = dx * dx + dy * dy + dz * dz;
        const float g = (li + L[j] + scorr(r2) * std::min(si, S[j])) * G[e];
        coincident += r2 <= tiny2 ? 1 : 0;
        dx_sum += g * dx;
        dy_sum += g * dy;
        dz_sum += g * dz;
      }
    }
    Eigen::Vector3f dp(dx_sum, dy_sum, dz_sum);
    if (coincident > 0) {  // rare: exact path with directions for coincident pairs
      dp.setZero();
      for (std::uint32_t e = off[i]; e < off[i + 1]; ++e) {
        const std::uint32_t j = nbr[e];
        float factor = li + L[j];
        if (scorr.on)
          factor += scorr((predicted_[i] - predicted_[j]).squaredNorm()) * std::min(S[i], S[j]);
        dp += factor * grad_scale * pairGradient(i, j);
      }
    }
    delta_[i] = dp;
    if (walls && li != 0.0f) {  // lambda_i times the solids' part of grad_i C_i
      float fraction = 0.0f;
      Eigen::Vector3f gw = Eigen::Vector3f::Zero();
      if (solids.density(predicted_[i], fraction, gw)) delta_[i] += li * gw;
    }
  }
}

SolidBoundaries PbfSolver::boundaries() const {
  // Particle centres stay half a spacing from every surface: sphere surfaces touch it,
  // and the initial lattice (first layer at d/2) is already in place.
  SolidBoundaries solids(container_, container_pose_, obstacles_, *lattice_,
                         0.5f * params_.particle_spacing);
  solids.setPreviousPoses(prev_container_pose_, &prev_obstacle_pose_);
  return solids;
}

void PbfSolver::applyDeltasAndBoundary() {
  const std::size_t n = size();
  const SolidBoundaries solids = boundaries();
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) predicted_[i] = solids.project(predicted_[i] + delta_[i]);
}

void PbfSolver::updateVelocities(float dt) {
  const std::size_t n = size();
  const float inv_dt = 1.0f / dt;
  const SolidBoundaries solids = boundaries();
  const float friction = params_.wall_friction;
  const float layer = params_.particle_spacing;
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    // With zero iterations the prediction itself may have left the box.
    Eigen::Vector3f p = solids.project(predicted_[i]);
    Eigen::Vector3f normal, surface_motion;
    if (friction > 0.0f && solids.contact(p, layer, normal, surface_motion)) {
      // Wall shear tau = rho0 c_f |u_t| u_t acts on the layer of thickness d next to the
      // surface: du_t/dt = -c_f |u_t| u_t / d. Backward Euler over the step gives
      // u_t' = u_t / (1 + c_f |u_t| dt / d), in displacements (t = u_t dt) below: stable at
      // any dt and converging to the same law as dt shrinks. The normal part of the motion
      // is the projection's business.
      const Eigen::Vector3f rel = (p - position_[i]) - surface_motion;
      const Eigen::Vector3f tangential = rel - rel.dot(normal) * normal;
      const float keep = 1.0f / (1.0f + friction * tangential.norm() / layer);
      p -= (1.0f - keep) * tangential;
      p = solids.project(p);
    }
    velocity_[i] = (p - position_[i]) * inv_dt;
    position_[i] = p;
  }
}

void PbfSolver::computeDensityAndVorticity() {
  const std::size_t n = size();
  const Kernels k(params_.supportRadius());
  const auto& off = grid_->offsets();
  const auto& nbr = grid_->indices();
  const float mass = params_.particleMass();
  const float self_density = mass * k.poly6(0.0f);
  const bool vorticity = params_.vorticity_epsilon > 0.0f;
  if (vorticity) vorticity_.resize(n);
  neighbor_count_.resize(n);
  const bool walls = params_.wall_density;
  const SolidBoundaries solids = boundaries();

  // Density first (vorticity needs every density).
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3f pi = position_[i];
    float rho = self_density;
    std::uint32_t count = 0;
    for (std::uint32_t e = off[i]; e < off[i + 1]; ++e) {
      const float r2 = (pi - position_[nbr[e]]).squaredNorm();
      if (r2 >= k.h2) continue;
      rho += mass * k.poly6(r2);
      ++count;
    }
    if (walls) {
      float fraction = 0.0f;
      Eigen::Vector3f unused = Eigen::Vector3f::Zero();
      if (solids.density(pi, fraction, unused)) rho += params_.rest_density * fraction;
    }
    density_[i] = rho;
    neighbor_count_[i] = static_cast<std::uint16_t>(std::min<std::uint32_t>(count, 65535));
  }
  if (!vorticity) return;
  // omega_i = sum_j V_j grad_i W_ij x (v_j - v_i): the SPH curl of the velocity.
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3f pi = position_[i], vi = velocity_[i];
    Eigen::Vector3f w = Eigen::Vector3f::Zero();
    for (std::uint32_t e = off[i]; e < off[i + 1]; ++e) {
      const std::uint32_t j = nbr[e];
      Pair p;
      p.r = pi - position_[j];
      p.r2 = p.r.squaredNorm();
      if (p.r2 >= k.h2) continue;
      p.rlen = std::sqrt(p.r2);
      w += (mass / density_[j]) * spikyGradientSafe(k, p, id_[i], id_[j]).cross(velocity_[j] - vi);
    }
    vorticity_[i] = w;
  }
}

void PbfSolver::applyViscosityAndVorticity(float dt) {
  const std::size_t n = size();
  const Kernels k(params_.supportRadius());
  const auto& off = grid_->offsets();
  const auto& nbr = grid_->indices();
  const float mass = params_.particleMass();
  const float c = params_.xsphCoefficient(dt);
  const bool vorticity = params_.vorticity_epsilon > 0.0f;
  const float veps = params_.vorticity_epsilon * k.h;  // f = epsilon h (N x omega)

#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3f pi = position_[i], vi = velocity_[i];
    Eigen::Vector3f xsph = Eigen::Vector3f::Zero();
    Eigen::Vector3f eta = Eigen::Vector3f::Zero();
    const float wi = vorticity ? vorticity_[i].norm() : 0.0f;
    for (std::uint32_t e = off[i]; e < off[i + 1]; ++e) {
      const std::uint32_t j = nbr[e];
      Pair p;
      p.r = pi - position_[j];
      p.r2 = p.r.squaredNorm();
      if (p.r2 >= k.h2) continue;
      const float vol = mass / density_[j];
      // XSPH (eq 10) with the m_j / rho_j factor.
      if (c > 0.0f) xsph += (vol * k.poly6(p.r2)) * (velocity_[j] - vi);
      if (vorticity) {
        p.rlen = std::sqrt(p.r2);
        // eta = grad |omega|, SPH difference form (exact for a constant field).
        eta += (vol * (vorticity_[j].norm() - wi)) * spikyGradientSafe(k, p, id_[i], id_[j]);
      }
    }
    Eigen::Vector3f v = vi + c * xsph;
    if (vorticity) {
      const float eta_len = eta.norm();
      // No gradient, no direction: confinement has nothing to amplify there.
      if (eta_len > 1e-12f) v += (dt * veps) * (eta / eta_len).cross(vorticity_[i]);
    }
    new_velocity_[i] = v;
  }
  velocity_.swap(new_velocity_);
}

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
