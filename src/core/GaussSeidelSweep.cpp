#include "pbf_ros/core/PbfSolver.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "BlockColours.h"
#include "ContainerMirror.h"
#include "DeterministicSum.h"
#include "FreeSurfaceLend.h"
#include "PackedSlots.h"
#include "NeighborSums.h"
#include "PairGeometry.h"
#include "PullRelaxation.h"
#include "pbf_ros/core/Boundaries.h"
#include "pbf_ros/core/Kernels.h"
#include "pbf_ros/core/NeighborGrid.h"

// The Gauss-Seidel solve (SolverParams::gauss_seidel): the density constraints projected one
// after another, each from the positions the projections before it left, as PBD projects
// its constraints (Mueller et al. 2007), instead of all at once from the same positions
// (Jacobi, JacobiSolve.cpp). A Jacobi iteration carries a correction one neighbourhood
// further; a sweep carries it as far as the order allows, so a column's pressure builds in
// fewer iterations (doc/performance.md, Gauss-Seidel).
//
// Constraint i at the current positions: C_i = rho_i / rho0 - 1 (only compression when
// unilateral), with its gradient with respect to x_i (the neighbours, the container's
// images of them and of i, the solids' density) and to every neighbour x_j (the pair and
// j's images seen from i). It takes lambda_i = -omega C_i / (sum_k |grad_k C_i|^2 + eps) and
// moves each of its particles by lambda_i grad_k C_i. The solids are projected onto once
// after the sweep, as after a Jacobi correction. The sums are NeighborSums' (AVX2 where the
// CPU has it), the moves are scattered one neighbour at a time.
//
// Order and threads: the blocks of cells of one phase (BlockColours.h: one colour) share no
// particle, so each phase's blocks are projected in parallel, a block by one thread, and the
// result does not depend on the thread count. A block's cells go top first along gravity,
// and a cell's particles highest first.

namespace pbf {

namespace {

// The linear part of a reflection applied to v (the map is symmetric: M^T v = M v).
Eigen::Vector3f reflectLinear(const Reflection& r, const Eigen::Vector3f& v) {
  const float* m = r.m;
  return {m[0] * v.x() + m[1] * v.y() + m[2] * v.z(), m[3] * v.x() + m[4] * v.y() + m[5] * v.z(),
          m[6] * v.x() + m[7] * v.y() + m[8] * v.z()};
}

// The image of x under a reflection: M x + b.
Eigen::Vector3f imageOf(const Reflection& r, const Eigen::Vector3f& x) {
  return reflectLinear(r, x) + Eigen::Vector3f(r.b[0], r.b[1], r.b[2]);
}

}  // namespace

// What every projection of one sweep shares. The sweep moves `position` (stride floats per
// particle): the 16-byte slots where the AVX2 sums read them (NeighborArrays::packed; one
// 128-bit load and store per neighbour moved), else predicted_ itself.
struct PbfSolver::SweepContext {
  Kernels k;
  PairConstants pc;
  NeighborArrays arrays;
  float* position;
  std::size_t stride;
  // Per thread, two rows of row_length floats (NeighborSums.h): the projected particle's
  // g of grad_i W = g (x_i - x_j) per neighbour, and the same for the image pairs by one
  // wall. They live for one projection only, so each thread reuses its own: arrays the size
  // of the lists, written and read back once per sweep, were memory traffic for nothing
  // beyond the caches (8 % of a 256k-particle step at one thread, doc/performance.md).
  float* rows;
  std::size_t row_length;
  float self_density, inv_rho0, grad_scale, eps, omega, rest_density;
  float pull_omega;  // a two-sided constraint's pulls are not over-relaxed (PullRelaxation.h)
  bool unilateral, walls;
  SolidBoundaries solids;
  ContainerMirror images;
  // The free surface's lend (FreeSurfaceLend.h; null when off), added to each density; the
  // table is set for the step's first sweep only, which lowers the lend from each particle's
  // one-sided gradient.
  float* lend;
  const FreeSurfaceLend* lower_lend;

  Eigen::Vector3f at(std::size_t j) const {
    const float* p = position + stride * j;
    return {p[0], p[1], p[2]};
  }
};

// The stop test measures the density after a sweep (a density pass, cheaper than a lambda
// pass), as the Jacobi solve's lambda pass does before each correction: what each constraint
// had when the sweep reached it (the sweep's own residual) overstates what is left after the
// sweep, and stopping on it took a third more sweeps. The last measurement is at the final
// positions, so the step's own density pass is skipped (ended_on_density).
//
// A measurement costs about half a sweep, and at tight tolerances a step sweeps 5-15 times:
// measured after every sweep, they were a fifth of the 1 m^3 dam break's time at 0.01 %. So
// a sweep is measured only where the measurement could pass: a step sweeps exactly as many
// times as when every sweep was measured, only measurements that would fail are left out.
namespace {

// Above this many times the tolerance, a sweep's own residual means an error after the
// sweep above the tolerance. The residual has overstated the error 1.24-2.81 times (every
// measurement of the tank at d = 0.02 and 0.01 m, at 0.3 % and 0.03 %, of the dam break at
// 0.3 % and of the 1 m^3 dam break at 0.01 %; the ratio grows from the first sweep to the
// last of a step, so no ratio measured early in a step bounds the later ones). Were it ever
// larger, a step would sweep once more than it needed, never less.
constexpr double kResidualOverstatesErrorAtMost = 4.0;

}  // namespace

bool PbfSolver::solveGaussSeidel(StepStats& stats, bool& ended_on_density) {
  const bool use_tolerance = params_.density_tolerance > 0.0f;
  // The step's summed multipliers (a warm start would start from them, were the solve
  // switched back to Jacobi with one).
  std::fill(lambda_sum_.begin(), lambda_sum_.end(), 0.0f);
  const double measure_below = kResidualOverstatesErrorAtMost * params_.density_tolerance;
  int sweeps = 0;
  ended_on_density = false;
  while (sweeps < params_.max_iterations) {
    const float swept = gaussSeidelSweep();
    if (!std::isfinite(swept)) return false;
    if (sweeps == 0) stats.initial_density_error = swept;
    ++sweeps;
    try {
      keepListsValidFor(predicted_, stats);
    } catch (const std::length_error&) {
      return false;
    }
    if (!use_tolerance || sweeps < params_.minIterations()) continue;
    if (sweeps < params_.max_iterations && swept > measure_below) continue;
    // A residual above the tolerance mostly means an error above it too: the measurement
    // may then stop as soon as it shows that (DensityMeasurement.cpp).
    double error = 0.0;
    bool stopped_early = false;
    const bool within = densityWithinTolerance(packed_->packPositions(predicted_), params_.density_tolerance,
                                               swept > params_.density_tolerance, error, stopped_early);
    ++stats.density_checks;
    if (stopped_early) ++stats.density_checks_stopped_early;
    if (!std::isfinite(error)) return false;
    stats.final_sweep_residual = swept;
    if (within) {
      ended_on_density = true;
      break;
    }
  }
  stats.iterations = sweeps;
  stats.iteration_cap_reached = use_tolerance && !ended_on_density;
  return true;
}

float PbfSolver::gaussSeidelSweep() {
  const std::size_t n = size();
  if (!colours_valid_) {
    if (grid_->pointCells().size() != n)
      throw std::logic_error("PbfSolver: neighbour lists do not match the particles");
    colours_->build(*grid_, predicted_, params_.gravity);
    gradient_row_length_ = gradientRowLength();  // the lists are new: so may be the longest
    colours_valid_ = true;
  }
  // Every sweep: the thread count may change between steps without new lists.
  const std::size_t rows_needed =
      2 * gradient_row_length_ * static_cast<std::size_t>(omp_get_max_threads());
  if (gradient_rows_.size() < rows_needed) gradient_rows_.resize(rows_needed);
  const Kernels k(params_.supportRadius());
  const float mass = params_.densityMass();
  const float grad_scale = mass / params_.rest_density;
  const ContainerMirror images = containerMirror();
  sweep_residual_.resize(n);
  // Wrench tracking reads the x,y,z array (ContainerMirror::forEachImage): no slots then.
  float* const slots = track_wrenches_ ? nullptr : packed_->sweepPositions(predicted_);
  float* const xyz = n == 0 ? nullptr : predicted_[0].data();
  const SweepContext sweep{k,
                           PairConstants{k.h, k.h2, 0.0f, mass * k.spiky_coef,
                                         grad_scale * k.spiky_grad_coef, kCoincident * k.h2},
                           NeighborArrays{xyz, grid_->offsets().data(), grid_->indices().data(), slots},
                           slots != nullptr ? slots : xyz,
                           slots != nullptr ? std::size_t{4} : std::size_t{3},
                           gradient_rows_.data(),
                           gradient_row_length_,
                           mass * k.spiky(0.0f),
                           1.0f / params_.rest_density,
                           grad_scale,
                           params_.cfmEpsilon(),
                           params_.gauss_seidel_omega * overlap_relaxation_,
                           params_.rest_density,
                           kPullRelaxation * overlap_relaxation_,
                           params_.unilateral_constraint,
                           params_.wall_density,
                           boundaries(),
                           images,
                           surface_lend_table_ ? surface_lend_.data() : nullptr,
                           surface_lend_set_ ? nullptr : surface_lend_table_.get()};
#pragma omp parallel
  {
    const int thread = omp_get_thread_num(), threads = omp_get_num_threads();
    const std::uint32_t* const order = colours_->order();
    float* const rows = sweep.rows + 2 * sweep.row_length * static_cast<std::size_t>(thread);
    for (std::size_t phase = 0; phase < colours_->phases(); ++phase) {
      const BlockColours::Block* blocks = colours_->first(phase);
      // Each thread takes one contiguous run of the phase's blocks (Morton order: one
      // region of the fluid) holding its share of the particles, so that the threads move
      // particles in different parts of memory: handed out a few cells at a time, they
      // shared cache lines of neighbours' positions, and two threads swept slower than one.
      // The barrier at the end of each phase is what keeps the phases apart.
      const auto [begin, end] = colours_->share(phase, thread, threads);
      for (std::size_t q = begin; q < end; ++q)
        for (std::uint32_t e = blocks[q].begin; e < blocks[q].end; ++e) projectDensityConstraint(order[e], sweep, rows);
#pragma omp barrier
    }
  }
  if (surface_lend_table_) surface_lend_set_ = true;
  if (slots == nullptr) {
    projectOntoSolids();
  } else {  // back from the slots, onto the solids (wrenches are not tracked here)
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) predicted_[i] = sweep.solids.project(sweep.at(i));
  }
  return static_cast<float>(
      deterministicSum(n, [&](std::size_t i) { return static_cast<double>(sweep_residual_[i]); }) /
      std::max<std::size_t>(n, 1));
}

// The longest neighbour list, rounded up so that the rows are rarely re-allocated as it
// changes (a warm step allocates nothing).
std::size_t PbfSolver::gradientRowLength() const {
  const std::uint32_t* off = grid_->offsets().data();
  std::uint32_t longest = 0;
#pragma omp parallel for reduction(max : longest) schedule(static)
  for (std::size_t i = 0; i < size(); ++i) longest = std::max(longest, off[i + 1] - off[i]);
  constexpr std::size_t kRound = 64;  // floats: whole cache lines, and room to grow
  return (std::size_t{longest} / kRound + 1) * kRound;
}

void PbfSolver::projectDensityConstraint(std::size_t i, const SweepContext& sweep, float* rows) {
  const Kernels& k = sweep.k;
  float* const W = sweep.position;
  const std::size_t S = sweep.stride;
  const Eigen::Vector3f x_i = sweep.at(i);
  const std::uint32_t* off = sweep.arrays.offset;
  const std::uint32_t* nbr = sweep.arrays.index;
  const std::uint32_t* const list = nbr + off[i];  // i's neighbours: G[e] is list[e]'s factor
  const std::uint32_t count = off[i + 1] - off[i];
  float* const G = rows;
  float* const GI = rows + sweep.row_length;
  Reflection refl[ContainerMirror::kMaxReflections];
  const int reflections = sweep.images.reflections(x_i, refl);
  const LambdaSums s =
      reflections == 0
          ? lambdaSums(sweep.arrays, sweep.pc, i, G)
          : lambdaSumsWithImages(sweep.arrays, sweep.pc, i, refl, reflections, G, GI);
  float rho = sweep.self_density + s.rho;
  Eigen::Vector3f grad_i(s.gx, s.gy, s.gz);
  float sum_grad2 = s.sum_grad2;

  // -grad_j C_i, and j's part of grad_i C_i, recomputed with directions for coincident pairs
  // (PairGeometry.h; the sums left them out) and with every image: for the few particles
  // with a coincident pair, or at an edge or a corner (several reflections, whose factors
  // the sums did not cache: their sums are right, their moves are recomputed).
  const bool exact = s.coincident > 0 || reflections > 1;
  auto exactPair = [&](std::uint32_t j, Eigen::Vector3f& part_of_grad_i) {
    const Eigen::Vector3f x_j = sweep.at(j);
    Pair p;
    p.r = x_i - x_j;
    p.r2 = p.r.squaredNorm();
    p.rlen = std::sqrt(p.r2);
    const Eigen::Vector3f direct =
        p.r2 < k.h2 ? Eigen::Vector3f(sweep.grad_scale * spikyGradientSafe(k, p, id_[i], id_[j]))
                    : Eigen::Vector3f::Zero();
    Eigen::Vector3f minus_grad_j = direct;
    part_of_grad_i = direct;
    for (int q = 0; q < reflections; ++q) {
      const Eigen::Vector3f r = x_i - imageOf(refl[q], x_j);
      const float r2 = r.squaredNorm();
      if (r2 >= k.h2 || r2 <= sweep.pc.coincident2) continue;
      const Eigen::Vector3f g = sweep.grad_scale * k.spikyGradient(r, std::sqrt(r2));
      part_of_grad_i += g;
      minus_grad_j += reflectLinear(refl[q], g);
    }
    return minus_grad_j;
  };
  if (s.coincident > 0) {
    grad_i.setZero();
    sum_grad2 = 0.0f;
    for (std::uint32_t e = 0; e < count; ++e) {
      Eigen::Vector3f part;
      sum_grad2 += exactPair(list[e], part).squaredNorm();
      grad_i += part;
    }
  }
  // i's own images move with i (twice as fast as i: see ConstraintPasses.cpp).
  Eigen::Vector3f own_images = Eigen::Vector3f::Zero();  // counted once: the lend's gradient
  for (int q = 0; q < reflections; ++q) {
    const Eigen::Vector3f r = x_i - imageOf(refl[q], x_i);
    const float rlen = r.norm();
    if (rlen >= k.h) continue;
    rho += sweep.pc.density * (k.h - rlen) * (k.h - rlen) * (k.h - rlen);
    if (rlen <= 0.0f) continue;
    const Eigen::Vector3f g = sweep.grad_scale * k.spikyGradient(r, rlen);
    grad_i += 2.0f * g;
    own_images += g;
  }
  if (sweep.walls) {  // the solids' density: they do not move, they add to grad_i C_i only
    float fraction = 0.0f;
    Eigen::Vector3f gw = Eigen::Vector3f::Zero();
    if (sweep.solids.density(x_i, fraction, gw)) {
      rho += sweep.rest_density * fraction;
      grad_i += gw;
    }
  }
  if (sweep.lend != nullptr) {
    if (sweep.lower_lend != nullptr)
      sweep.lend[i] = sweep.lower_lend->lowered(sweep.lend[i], (grad_i - own_images).norm(), sweep.rest_density);
    rho += sweep.lend[i];
  }
  float c = rho * sweep.inv_rho0 - 1.0f;
  sweep_residual_[i] = std::max(c, 0.0f);  // NaN stays NaN: the sweep's error then is too
  if (sweep.unilateral) c = std::max(c, 0.0f);
  const float denom = sum_grad2 + grad_i.squaredNorm() + sweep.eps;
  if (c == 0.0f || !(denom > 0.0f)) return;
  const float lambda = -(c < 0.0f ? sweep.pull_omega : sweep.omega) * c / denom;
  lambda_sum_[i] += lambda;
  if (track_wrenches_) recordGaussSeidelBoundaryPush(i, lambda, sweep);

  // The neighbours first: their gradients are taken at i's position before it moves.
  if (exact) {
    for (std::uint32_t e = 0; e < count; ++e) {
      const std::uint32_t j = list[e];
      Eigen::Vector3f unused;
      const Eigen::Vector3f move = -lambda * exactPair(j, unused);
      for (int c = 0; c < 3; ++c) W[S * j + c] += move[c];
    }
  } else if (S == 4) {  // slots: one 16-byte load and store per neighbour (w stays 0)
    using Slot = Eigen::Map<Eigen::Vector4f, Eigen::Aligned16>;
    const Eigen::Vector4f xi(x_i.x(), x_i.y(), x_i.z(), 0.0f);
    if (reflections == 0) {
      for (std::uint32_t e = 0; e < count; ++e) {
        Slot xj(W + 4 * std::size_t{list[e]});
        xj -= (lambda * G[e]) * (xi - xj);  // grad_j C_i = -G (x_i - x_j)
      }
    } else {  // one wall: grad_j C_i = -G (x_i - x_j) - GI (R x_i - x_j), R x_i i's image
      const Eigen::Vector3f r = imageOf(refl[0], x_i);
      const Eigen::Vector4f ri(r.x(), r.y(), r.z(), 0.0f);
      for (std::uint32_t e = 0; e < count; ++e) {
        Slot xj(W + 4 * std::size_t{list[e]});
        xj -= (lambda * G[e]) * (xi - xj) + (lambda * GI[e]) * (ri - xj);
      }
    }
  } else {
    const Eigen::Vector3f ri = reflections == 0 ? x_i : imageOf(refl[0], x_i);
    const float* image_factor = reflections == 0 ? nullptr : GI;
    for (std::uint32_t e = 0; e < count; ++e) {
      float* xj = W + 3 * std::size_t{list[e]};
      const float f = lambda * G[e], fi = image_factor != nullptr ? lambda * image_factor[e] : 0.0f;
      for (int c = 0; c < 3; ++c) xj[c] -= f * (x_i[c] - xj[c]) + fi * (ri[c] - xj[c]);
    }
  }
  for (int c = 0; c < 3; ++c) W[S * i + c] += lambda * grad_i[c];
}

// What the solids did to the fluid in one projection (wrench tracking, WrenchTracking.cpp):
// the container's part is what the images leave unbalanced. Particle i moves by lambda g and
// j by -lambda M g for an image pair (i, image of j) with gradient g, i by lambda (I - M) g
// for its own image: net lambda (I - M) g either way, twice g's component along each
// reflected axis, which goes to that wall. The obstacles' and walls' density adds
// lambda times their part of grad_i C_i, as in the Jacobi pass.
void PbfSolver::recordGaussSeidelBoundaryPush(std::size_t i, float lambda, const SweepContext& sweep) {
  const int thread = omp_get_thread_num();
  const Eigen::Vector3f x = sweep.at(i);
  sweep.images.forEachImage(i, sweep.arrays, sweep.k.h2,
                            [&](std::uint32_t, const Eigen::Vector3f& r, float r2, bool, int walls) {
                              if (r2 <= sweep.pc.coincident2) return;
                              const Eigen::Vector3f push =
                                  2.0f * lambda * sweep.grad_scale * sweep.k.spikyGradient(r, std::sqrt(r2));
                              for (int face = 0; face < SolidBoundaries::kContainerFaces; ++face) {
                                if (!(walls & (1 << face))) continue;
                                const Eigen::Vector3f axis = sweep.images.axis(face / 2);
                                wrench_sums_.add(thread, face, x, axis.dot(push) * axis);
                              }
                            });
  sweep.solids.densityGradientParts(x, [&](int solid, const Eigen::Vector3f& gradient) {
    wrench_sums_.add(thread, solid, x, lambda * gradient);
  });
}

}  // namespace pbf
