#include "pbf_ros/core/PbfSolver.h"

#include <omp.h>

#include <algorithm>
#include <cmath>

#include "ContainerMirror.h"
#include "DeterministicSum.h"
#include "FreeSurfaceLend.h"
#include "NeighborSums.h"
#include "PackedSlots.h"
#include "PairGeometry.h"
#include "PullRelaxation.h"
#include "pbf_ros/core/Boundaries.h"
#include "pbf_ros/core/Kernels.h"
#include "pbf_ros/core/LatticeBoundary.h"
#include "pbf_ros/core/NeighborGrid.h"

// The density constraint's passes: lambda (eq 8-11), s_corr and delta p (eq 12-14), and the
// solids' projection of the corrected positions.

namespace pbf {

namespace {

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

// A warm start applies pressure before the solve has seen this step's positions; where it
// over-pushes, the fluid expands, and a compression-only pass would leave that expansion to
// become velocity. So with a warm start the step's summed multiplier is projected instead
// (kept <= 0: a particle can be pushed, or have its push taken back, never pulled), and the
// tolerance applies to what is left to correct, compression and over-push alike. A take-back
// is a pull, relaxed as every pull is (PullRelaxation.h); pushes stay unrelaxed, as in the
// cold solve, whose overshoot the projection now absorbs.

}  // namespace

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

void PbfSolver::computeLambdas(float& avg_error, LambdaPass pass) {
  const std::size_t n = size();
  const Kernels k(params_.supportRadius());
  const std::uint32_t* off = grid_->offsets().data();
  const std::uint32_t* nbr = grid_->indices().data();
  const float* P = predicted_.empty() ? nullptr : predicted_[0].data();
  const float mass = params_.densityMass();
  const float inv_rho0 = 1.0f / params_.rest_density;
  const float grad_scale = mass * inv_rho0;  // grad C = (m / rho0) grad W (eq 7 with mass)
  const float self_density = mass * k.spiky(0.0f);
  const bool unilateral = params_.unilateral_constraint;
  const float eps = params_.cfmEpsilon();
  const float relaxation = overlap_relaxation_;  // 1 at h = 2d
  const NeighborArrays arrays{P, off, nbr, packed_->packPositions(predicted_)};
  float* const lambda_slots = packed_->lambdaSlots();  // (x*, lambda) for the delta-p pass
  const PairConstants pc{k.h, k.h2, 0.0f, mass * k.spiky_coef,
                         grad_scale * k.spiky_grad_coef, kCoincident * k.h2};
  const bool walls = params_.wall_density;
  const SolidBoundaries solids = boundaries();
  const ContainerMirror images = containerMirror();
  // The delta-p pass of this iteration sees the same positions: it reuses each pair's
  // gradient factor instead of another sqrt and division.
  pair_gradient_.resize(grid_->indices().size());
  float* G = pair_gradient_.data();
  // Image pairs of particles by one wall: written for those particles' entries only.
  image_gradient_.resize(images.isOn() ? grid_->indices().size() : 0);
  float* GI = image_gradient_.data();
  has_coincident_pair_.resize(n);
  neighbor_count_.resize(n);
  if (walls) wall_gradient_.resize(n);
  // A warm-started or accelerated solve may take back what it pushed (kPullRelaxation).
  const bool projected = params_.projectedSolve();
  if (projected) complementarity_residual_.resize(n);
  float* const lend = surface_lend_table_ ? surface_lend_.data() : nullptr;
  // Set while this is the step's first pass: it lowers the lend.
  const FreeSurfaceLend* const lower_lend = surface_lend_set_ ? nullptr : surface_lend_table_.get();

#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    // The container's images are neighbours like any other (ContainerMirror.h); i's own
    // images move with i, so their distance changes twice as fast.
    Reflection refl[ContainerMirror::kMaxReflections];
    const int reflections = images.reflections(predicted_[i], refl);
    float* const row = G + off[i];  // i's entries of the per-pair arrays
    float* const image_row = images.isOn() ? GI + off[i] : nullptr;
    const LambdaSums s = reflections == 0 ? lambdaSums(arrays, pc, i, row)
                                          : lambdaSumsWithImages(arrays, pc, i, refl, reflections, row, image_row);
    has_coincident_pair_[i] = s.coincident > 0;  // the delta-p pass sees the same positions
    neighbor_count_[i] = static_cast<std::uint16_t>(std::min<std::uint32_t>(s.within, 65535));
    float rho = self_density + s.rho, gx = s.gx, gy = s.gy, gz = s.gz, sum_grad2 = s.sum_grad2;
    if (s.coincident > 0) {  // rare: redo the gradients with directions for coincident pairs
      Eigen::Vector3f gi = Eigen::Vector3f::Zero();
      sum_grad2 = 0.0f;
      for (std::uint32_t e = off[i]; e < off[i + 1]; ++e) {
        const Eigen::Vector3f g = grad_scale * pairGradient(i, nbr[e]);
        gi += g;
        sum_grad2 += g.squaredNorm();
      }
      for (int q = 0; q < reflections; ++q) {  // images as separate neighbours here
        const LambdaSums m = imageLambdaSums(arrays, pc, i, refl[q]);
        gi += Eigen::Vector3f(m.gx, m.gy, m.gz);
        sum_grad2 += m.sum_grad2;
      }
      gx = gi.x(), gy = gi.y(), gz = gi.z();
    }
    Eigen::Vector3f own_images = Eigen::Vector3f::Zero();  // counted once: the lend's gradient
    for (int q = 0; q < reflections; ++q) {
      const Eigen::Vector3f r = ContainerMirror::imageOffset(refl[q], P, i, i);
      const float rlen = r.norm();
      if (rlen >= k.h) continue;
      rho += mass * k.spiky(rlen);
      if (rlen <= 0.0f) continue;
      const Eigen::Vector3f g = grad_scale * k.spikyGradient(r, rlen);
      own_images += g;
      gx += 2.0f * g.x(), gy += 2.0f * g.y(), gz += 2.0f * g.z();
    }
    if (walls) {  // obstacles do not move with the solve: they add to grad_i C only
      float fraction = 0.0f;
      Eigen::Vector3f gw = Eigen::Vector3f::Zero();
      if (solids.density(predicted_[i], fraction, gw)) {
        rho += params_.rest_density * fraction;
        gx += gw.x(), gy += gw.y(), gz += gw.z();
      }
      wall_gradient_[i] = gw;  // the delta-p pass sees the same position
    }
    if (lend != nullptr) {  // the free surface's (FreeSurfaceLend.h), lowered by the first pass
      if (lower_lend != nullptr) {
        const Eigen::Vector3f one_sided = Eigen::Vector3f(gx, gy, gz) - own_images;
        lend[i] = lower_lend->lowered(lend[i], one_sided.norm(), params_.rest_density);
      }
      rho += lend[i];
    }
    density_[i] = rho;
    float li = lambda_sum_[i];  // the warm start (<= 0), which lambda_sum_ holds
    if (pass == LambdaPass::kNewton) {
      float c = rho * inv_rho0 - 1.0f;
      // Projected, an expanded particle's negative c may take back its push (below).
      if (unilateral && !projected) c = std::max(c, 0.0f);
      const float denom = sum_grad2 + gx * gx + gy * gy + gz * gz + eps;
      const float step = c == 0.0f || !(denom > 0.0f) ? 0.0f : -relaxation * c / denom;
      li = step > 0.0f ? kPullRelaxation * step : step;  // a two-sided constraint's pull
      if (projected) {
        // The step's summed multiplier stays <= 0: push, or take a push back (relaxed).
        const float before = lambda_sum_[i];
        li = std::min(before + li, 0.0f) - before;
        // What is left to correct: the compression, or the expansion that a push caused.
        complementarity_residual_[i] = c > 0.0f ? c : std::min(-c, -before * denom);
      }
    }
    lambda_[i] = li;
    if (lambda_slots != nullptr) {
      float* slot = lambda_slots + 4 * i;
      slot[0] = P[3 * i], slot[1] = P[3 * i + 1], slot[2] = P[3 * i + 2], slot[3] = li;
    }
  }
  if (lend != nullptr) surface_lend_set_ = true;
  if (projected && pass == LambdaPass::kNewton) {
    avg_error = static_cast<float>(
        deterministicSum(n, [&](std::size_t i) {
          return static_cast<double>(complementarity_residual_[i]);
        }) / std::max<std::size_t>(n, 1));
    return;
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
  const float grad_scale = params_.densityMass() / params_.rest_density;
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

void PbfSolver::correctPositions(LambdaPass pass) {
  const std::size_t n = size();
  const Kernels k(params_.supportRadius());
  const std::uint32_t* off = grid_->offsets().data();
  const std::uint32_t* nbr = grid_->indices().data();
  const float* P = predicted_.empty() ? nullptr : predicted_[0].data();
  const float* L = lambda_.data();
  const float* G = pair_gradient_.data();  // (m / rho0) grad W / r, from the lambda pass
  const float* GI = image_gradient_.data();  // the same for image pairs by one wall
  const float grad_scale = params_.densityMass() / params_.rest_density;
  const float tiny2 = kCoincident * k.h2;
  // With k = 0 the loop without s_corr runs: no cost.
  Scorr scorr(params_, k, current_dt_);
  scorr.on = scorr.on && pass == LambdaPass::kNewton;  // the warm start re-applies no s_corr
  const bool sum_lambda = pass == LambdaPass::kNewton;  // the warm start is already summed
  if (scorr.on) computeScorrScales(scorr);
  const float* S = scorr.on ? scorr_scale_.data() : nullptr;
  const NeighborArrays arrays{P, off, nbr, packed_->lambdaSlots()};  // filled by the lambda pass
  const bool walls = params_.wall_density;
  const ContainerMirror images = containerMirror();
  const PairConstants image_pc{k.h, k.h2, 0.0f, 0.0f, grad_scale * k.spiky_grad_coef, tiny2};
  // The corrected positions go to a second buffer, projected onto the solids in the same
  // pass (one pass and one barrier less per iteration); the neighbours still read the
  // uncorrected ones. Wrench tracking keeps delta p apart, to attribute it to the solids.
  const bool fused = !track_wrenches_;
  const SolidBoundaries solids = boundaries();
  if (fused) corrected_.resize(n);

#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const float xi = P[3 * i], yi = P[3 * i + 1], zi = P[3 * i + 2];
    const float li = L[i];
    Reflection refl[ContainerMirror::kMaxReflections];
    const int reflections = images.reflections(predicted_[i], refl);
    // By one wall (the common case near walls), the images' pairs ride along with the
    // direct ones, from the gradients the lambda pass cached.
    bool neighbour_images_done = false;
    float dx_sum = 0.0f, dy_sum = 0.0f, dz_sum = 0.0f;
    const bool coincident = has_coincident_pair_[i];  // counted by the lambda pass
    if (!scorr.on) {
      neighbour_images_done = reflections == 1 && !coincident;
      const VectorSum s = neighbour_images_done
                              ? deltaSumsWithImage(arrays, i, refl[0], L, G + off[i], GI + off[i])
                              : deltaSums(arrays, i, L, G + off[i]);
      dx_sum = s.x, dy_sum = s.y, dz_sum = s.z;
    } else {
      const float si = S[i];
#pragma omp simd reduction(+ : dx_sum, dy_sum, dz_sum)
      for (std::uint32_t e = off[i]; e < off[i + 1]; ++e) {
        const std::uint32_t j = nbr[e];
        const float dx = xi - P[3 * j], dy = yi - P[3 * j + 1], dz = zi - P[3 * j + 2];
        const float r2 = dx * dx + dy * dy + dz * dz;
        const float g = (li + L[j] + scorr(r2) * std::min(si, S[j])) * G[e];
        dx_sum += g * dx;
        dy_sum += g * dy;
        dz_sum += g * dz;
      }
    }
    Eigen::Vector3f dp(dx_sum, dy_sum, dz_sum);
    if (coincident) {  // rare: exact path with directions for coincident pairs
      dp.setZero();
      for (std::uint32_t e = off[i]; e < off[i + 1]; ++e) {
        const std::uint32_t j = nbr[e];
        float factor = li + L[j];
        if (scorr.on)
          factor += scorr((predicted_[i] - predicted_[j]).squaredNorm()) * std::min(S[i], S[j]);
        dp += factor * grad_scale * pairGradient(i, j);
      }
    }
    if (reflections > 0) dp += imagePush(arrays, image_pc, i, refl, reflections, neighbour_images_done);
    if (sum_lambda) lambda_sum_[i] += li;
    if (walls) dp += li * wall_gradient_[i];  // lambda_i times the solids' part of grad_i C_i
    if (fused)
      corrected_[i] = solids.project(predicted_[i] + dp);
    else
      delta_[i] = dp;
  }
  if (fused) {
    predicted_.swap(corrected_);
    return;
  }
  if (walls) recordBoundaryDensityPush(solids);
  applyDeltasRecordingBoundary(solids);  // not fused: wrenches are tracked
}

// The delta-p of particle i from the container's images: (lambda_i + lambda_j) grad W per
// image pair, as for any pair (unless the caller summed those already); i's own image pushes
// with 2 lambda_i. s_corr has no images.
Eigen::Vector3f PbfSolver::imagePush(const NeighborArrays& arrays, const PairConstants& pc,
                                     std::size_t i, const Reflection* refl, int reflections,
                                     bool neighbour_images_done) const {
  const float* P = arrays.position;
  const float h = pc.h, spiky = pc.spiky;
  Eigen::Vector3f push = Eigen::Vector3f::Zero();
  for (int q = 0; q < reflections; ++q) {
    if (!neighbour_images_done) {
      const VectorSum s = imageDeltaSums(arrays, pc, i, refl[q], lambda_.data());
      push += Eigen::Vector3f(s.x, s.y, s.z);
    }
    const Eigen::Vector3f r = ContainerMirror::imageOffset(refl[q], P, i, i);
    const float rlen = r.norm();
    if (rlen > 0.0f && rlen < h) push += (2.0f * lambda_[i] * spiky * (h - rlen) * (h - rlen) / rlen) * r;
  }
  return push;
}

ContainerMirror PbfSolver::containerMirror() const {
  return ContainerMirror(params_.wall_density ? container_ : Eigen::AlignedBox3f(), container_pose_,
                         params_.supportRadius(), 0.5f * params_.particle_spacing);
}

SolidBoundaries PbfSolver::boundaries() const {
  // Particle centres stay half a spacing from every surface: sphere surfaces touch it,
  // and the initial lattice (first layer at d/2) is already in place.
  SolidBoundaries solids(container_, container_pose_, obstacles_, *lattice_,
                         0.5f * params_.particle_spacing);
  solids.setPreviousPoses(prev_container_pose_, &prev_obstacle_pose_);
  if (!fluid_reach_.isEmpty()) solids.keepOnlyObstaclesNear(fluid_reach_);
  return solids;
}

void PbfSolver::projectOntoSolids() {
  const std::size_t n = size();
  const SolidBoundaries solids = boundaries();
  if (!track_wrenches_) {
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) predicted_[i] = solids.project(predicted_[i]);
    return;
  }
#pragma omp parallel
  {
    const int thread = omp_get_thread_num();
#pragma omp for schedule(static)
    for (std::size_t i = 0; i < n; ++i)
      predicted_[i] = solids.project(predicted_[i], [&](int solid, const Eigen::Vector3f& x, const Eigen::Vector3f& dx) {
        wrench_sums_.add(thread, solid, x, dx);
      });
  }
}

}  // namespace pbf
