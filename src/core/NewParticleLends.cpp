#include "pbf_ros/core/PbfSolver.h"

#include <omp.h>

#include <algorithm>

#include "ContainerMirror.h"
#include "FreeSurfaceLend.h"
#include "NeighborSums.h"
#include "PackedSlots.h"
#include "PairGeometry.h"
#include "pbf_ros/core/Boundaries.h"
#include "pbf_ros/core/Kernels.h"
#include "pbf_ros/core/NeighborGrid.h"

// The free surface's lend of the particles that have none yet (a fresh scene, an emitted
// block), measured where they entered the fluid: at the positions the step starts from.
//
// The step's first pass would otherwise measure it at the predicted positions, where gravity
// has already pushed the fluid into the solids: in one step of 1/60 s the column moves
// 0.136 d into the floor, the layers over it become one-sided, and the lend (which reads
// how one-sided a neighbourhood is) took them for a free surface. Lent density they do not
// miss, they looked compressed by up to 27 %: the first sweep left twice the tolerance, the
// sweeps that followed drifted the floor's layers sideways, and the dam break's first step
// reached 8.8 g dt (10.5 at d = 0.0125 m). Measured here, a resting lattice is lent only at
// its free surface, whatever the step; the first pass then only lowers it (FreeSurfaceLend.h).

namespace pbf {

void PbfSolver::measureNewLends() {
  if (!surface_lend_table_) return;
  const std::size_t n = size();
  const bool any_new = std::any_of(surface_lend_.begin(), surface_lend_.end(),
                                   [](float lend) { return lend < 0.0f; });  // kUnmeasured
  if (!any_new) return;
  // Lists at the positions the step starts from (the step rebuilds its own after the
  // prediction; a search that overflows throws std::length_error, which rejects the attempt).
  predicted_ = position_;
  updateFluidReach();
  rebuildNeighborLists(predicted_);

  const Kernels k(params_.supportRadius());
  const float mass = params_.densityMass();
  const float grad_scale = mass / params_.rest_density;
  const std::uint32_t* off = grid_->offsets().data();
  const std::uint32_t* nbr = grid_->indices().data();
  const float* P = predicted_.empty() ? nullptr : predicted_[0].data();
  const NeighborArrays arrays{P, off, nbr, packed_->packPositions(predicted_)};
  const PairConstants pc{k.h, k.h2, 0.0f, mass * k.spiky_coef, grad_scale * k.spiky_grad_coef,
                         kCoincident * k.h2};
  const SolidBoundaries solids = boundaries();
  const ContainerMirror images = containerMirror();
  const FreeSurfaceLend& table = *surface_lend_table_;

#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    if (!(surface_lend_[i] < 0.0f)) continue;
    // The gradient the first pass reads (ConstraintPasses.cpp, GaussSeidelSweep.cpp): the
    // neighbours', their images', i's own images once, the solids'.
    Eigen::Vector3f one_sided = Eigen::Vector3f::Zero();
    for (std::uint32_t e = off[i]; e < off[i + 1]; ++e) one_sided += grad_scale * pairGradient(i, nbr[e]);
    Reflection refl[ContainerMirror::kMaxReflections];
    const int reflections = images.reflections(predicted_[i], refl);
    for (int q = 0; q < reflections; ++q) {
      const LambdaSums m = imageLambdaSums(arrays, pc, i, refl[q]);
      one_sided += Eigen::Vector3f(m.gx, m.gy, m.gz);
      const Eigen::Vector3f r = ContainerMirror::imageOffset(refl[q], P, i, i);
      const float rlen = r.norm();
      if (rlen < k.h && rlen > 0.0f) one_sided += grad_scale * k.spikyGradient(r, rlen);
    }
    if (params_.wall_density) {
      float fraction = 0.0f;
      Eigen::Vector3f gw = Eigen::Vector3f::Zero();
      if (solids.density(predicted_[i], fraction, gw)) one_sided += gw;
    }
    surface_lend_[i] = table.lowered(FreeSurfaceLend::kUnmeasured, one_sided.norm(), params_.rest_density);
  }
}

}  // namespace pbf
