// Wrench tracking (SolidWrench.h): the passes that, only while PbfSolver::setWrenchTracking
// is on, record what each solid does to the particles. The friction and final projection
// are recorded inside updateVelocities (VelocityPasses.cpp), which shares its code.
#include <omp.h>

#include "pbf_ros/core/Boundaries.h"
#include "pbf_ros/core/PbfSolver.h"

namespace pbf {

// The solids' share of the delta-p pass: lambda_i times each solid's part of grad_i C_i
// (computeDeltas added their sum to delta_i). Run after that pass, so the pass itself is
// unchanged when nobody asks.
void PbfSolver::recordBoundaryDensityPush(const SolidBoundaries& solids) {
  const std::size_t n = size();
#pragma omp parallel
  {
    const int thread = omp_get_thread_num();
#pragma omp for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      const float li = lambda_[i];
      if (li == 0.0f) continue;
      const Eigen::Vector3f x = predicted_[i];
      solids.densityGradientParts(x, [&](int solid, const Eigen::Vector3f& gradient) {
        wrench_sums_.add(thread, solid, x, li * gradient);
      });
    }
  }
}

// applyDeltasAndBoundary, recording what each projection did.
void PbfSolver::applyDeltasRecordingBoundary(const SolidBoundaries& solids) {
  const std::size_t n = size();
#pragma omp parallel
  {
    const int thread = omp_get_thread_num();
#pragma omp for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      predicted_[i] = solids.project(
          predicted_[i] + delta_[i], [&](int solid, const Eigen::Vector3f& x, const Eigen::Vector3f& dx) {
            wrench_sums_.add(thread, solid, x, dx);
          });
    }
  }
}

}  // namespace pbf
