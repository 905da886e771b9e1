// Wrench tracking (SolidWrench.h): the passes that, only while PbfSolver::setWrenchTracking
// is on, record what each solid does to the particles. The friction and final projection
// are recorded inside updateVelocities (VelocityPasses.cpp), which shares its code.
#include <omp.h>

#include <cmath>

#include "ContainerMirror.h"
#include "pbf_ros/core/Boundaries.h"
#include "pbf_ros/core/Kernels.h"
#include "pbf_ros/core/NeighborGrid.h"
#include "pbf_ros/core/PbfSolver.h"

namespace pbf {

// The solids' share of the delta-p pass: lambda_i times each solid's part of grad_i C_i
// (correctPositions added their sum to delta_i). Run after that pass, so the pass itself is
// unchanged when nobody asks.
// The container's share is its images' push (imagePush): each image belongs to the walls it
// is reflected across, and each wall takes the push's component along its own axis. The
// components along the other axes cancel between the pairs (i, image of j) and (j, image
// of i); they go to the first wall, so that the walls' total is exactly the images' total.
void PbfSolver::recordBoundaryDensityPush(const SolidBoundaries& solids) {
  const std::size_t n = size();
  const Kernels k(params_.supportRadius());
  const ContainerMirror images = containerMirror();
  const float grad_scale = params_.densityMass() / params_.rest_density;
  const NeighborArrays arrays{predicted_.empty() ? nullptr : predicted_[0].data(),
                              grid_->offsets().data(), grid_->indices().data()};
#pragma omp parallel
  {
    const int thread = omp_get_thread_num();
#pragma omp for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      const float li = lambda_[i];
      const Eigen::Vector3f x = predicted_[i];
      images.forEachImage(i, arrays, k.h2,
                          [&](std::uint32_t j, const Eigen::Vector3f& r, float r2, bool self, int walls) {
                            const float factor = self ? 2.0f * li : li + lambda_[j];
                            if (r2 <= 0.0f || factor == 0.0f) return;
                            Eigen::Vector3f rest = factor * grad_scale * k.spikyGradient(r, std::sqrt(r2));
                            int first = -1;
                            for (int face = 0; face < SolidBoundaries::kContainerFaces; ++face) {
                              if (!(walls & (1 << face))) continue;
                              const Eigen::Vector3f axis = images.axis(face / 2);
                              const Eigen::Vector3f along = axis.dot(rest) * axis;
                              wrench_sums_.add(thread, face, x, along);
                              rest -= along;
                              if (first < 0) first = face;
                            }
                            wrench_sums_.add(thread, first, x, rest);
                          });
      if (li == 0.0f) continue;
      solids.densityGradientParts(x, [&](int solid, const Eigen::Vector3f& gradient) {
        wrench_sums_.add(thread, solid, x, li * gradient);
      });
    }
  }
}

// The delta-p pass kept apart (wrench tracking): delta p applied and projected onto the
// solids, recording what each projection did.
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
