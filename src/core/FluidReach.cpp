#include "pbf_ros/core/PbfSolver.h"

#include <omp.h>

#include <algorithm>

// The region the particles can occupy during one step, so that solids far from the fluid
// (a robot's links beside the tank) cost nothing per particle (Boundaries.h,
// keepOnlyObstaclesNear). Computed once per attempt, after the prediction.

namespace pbf {

namespace {
// Beyond the box of where the particles start and where gravity and their velocity take
// them, the constraint's corrections move them by much less than a spacing in a step (the
// CFL step and the speed cap see to it); two support radii are a wide margin. A particle
// that got farther would meet a far obstacle a step late, then be pushed out like any other.
constexpr float kReachMarginInSupportRadii = 2.0f;
}  // namespace

void PbfSolver::updateFluidReach() {
  fluid_reach_.setEmpty();
  if (obstacles_.empty() || position_.empty()) return;  // nothing to cull
  const std::size_t n = size();
  float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
#pragma omp parallel for reduction(min : lo[:3]) reduction(max : hi[:3]) schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min({lo[a], position_[i][a], predicted_[i][a]});
      hi[a] = std::max({hi[a], position_[i][a], predicted_[i][a]});
    }
  }
  const float margin = kReachMarginInSupportRadii * params_.supportRadius();
  fluid_reach_ = Eigen::AlignedBox3f(Eigen::Vector3f(lo[0], lo[1], lo[2]) - Eigen::Vector3f::Constant(margin),
                                     Eigen::Vector3f(hi[0], hi[1], hi[2]) + Eigen::Vector3f::Constant(margin));
}

}  // namespace pbf
