#include "pbf_ros/core/PbfSolver.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "pbf_ros/core/ChebyshevAcceleration.h"
#include "pbf_ros/core/NeighborGrid.h"

// Neighbour lists: built on a Morton-sorted grid, reused within the skin, and rebuilt as
// soon as any particle (moved by the step or by the solver's corrections) leaves it.

namespace pbf {

namespace {

// The fluid's bottom along gravity starts the grid's cells (GridAnchor) when
// gravity is along an axis (within ~8 degrees); a tilted gravity has no such layer.
GridAnchor gravityAnchor(const Eigen::Vector3f& g) {
  int axis = 0;
  g.cwiseAbs().maxCoeff(&axis);
  if (!(std::abs(g[axis]) > 0.99f * g.norm())) return {};
  return {axis, g[axis] > 0.0f};
}

}  // namespace

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
  permute(lambda_sum_, reorder_float_scratch_);  // the warm start follows its particle
  permute(surface_lend_, reorder_float_scratch_);  // and so does the free surface's lend
  chebyshev_->reorder(order, reorder_scratch_);   // mid-solve rebuilds only
}

// Reused lists stay exact while every particle is within half the skin of where it was at
// the build: then no pair closer than h now was farther than h + skin then.
bool PbfSolver::listsStillValidFor(const std::vector<Eigen::Vector3f>& points) const {
  const float skin = params_.neighbor_skin * params_.supportRadius();
  if (skin <= 0.0f || !lists_valid_ || build_position_.size() != points.size()) return false;
  const float limit2 = 0.25f * skin * skin;
  float moved2 = 0.0f;
#pragma omp parallel for reduction(max : moved2) schedule(static)
  for (std::size_t i = 0; i < points.size(); ++i)
    moved2 = std::max(moved2, (points[i] - build_position_[i]).squaredNorm());
  return moved2 < limit2;
}

void PbfSolver::updateNeighbors(StepStats& stats) {
  if (listsStillValidFor(predicted_)) {
    stats.neighbor_lists_reused = true;
    return;
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
  reorder(grid_->build(points, radius, domain, gravityAnchor(params_.gravity)));
  try {
    grid_->findNeighbors(points, radius, neighborPairBound());  // `points` was permuted by reorder()
  } catch (const std::length_error&) {
    attempt_too_dense_ = true;  // the step is rejected (PbfSolver::stepWith says why)
    throw;
  }
  if (params_.neighbor_skin > 0.0f) build_position_ = points;
  lists_valid_ = true;
  colours_valid_ = false;  // the Gauss-Seidel order follows the new cells
}

std::size_t PbfSolver::neighborPairBound() const {
  // A particle at rest density has (4/3) pi (f (1 + skin))^3 lattice neighbours within the
  // search radius (33 at the default f = 2). Eight times that on average means the fluid is
  // eight times denser than water, which the density constraint never allows: a collapse
  // (a step far too long for the forces), not a flow. Bounding the lists there keeps such a
  // state's search to megabytes and milliseconds instead of gigabytes and seconds; the
  // floor keeps small hostile starts (the stress matrix's 1000 particles at one point)
  // solvable.
  constexpr double kDenserThanAnyFluid = 8.0;
  constexpr double kFloor = double(std::size_t(1) << 22);
  const double reach = params_.support_radius_factor * (1.0 + params_.neighbor_skin);
  const double at_rest = 4.0 / 3.0 * 3.14159265358979 * reach * reach * reach;
  const double bound = std::max(kFloor, kDenserThanAnyFluid * at_rest * double(size()));
  return static_cast<std::size_t>(std::min(bound, double(NeighborGrid::kMaxPairs)));
}

// The solver's corrections move particles too, so the skin is checked after each of them,
// not only once per step; a particle that went too far triggers a rebuild right there.
bool PbfSolver::keepListsValidFor(const std::vector<Eigen::Vector3f>& points, StepStats& stats) {
  if (params_.neighbor_skin <= 0.0f) return false;  // built once per step on the predicted positions
  if (listsStillValidFor(points)) return false;
  rebuildNeighborLists(points);
  ++stats.neighbor_rebuilds_in_step;
  return true;
}

}  // namespace pbf
