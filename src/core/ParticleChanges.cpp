#include "pbf_ros/core/PbfSolver.h"

#include <limits>
#include <stdexcept>
#include <string>

#include "FreeSurfaceLend.h"

// Particles that enter and leave between steps (sources, drains, ~emit). Every per-particle
// array that lives across steps grows or shrinks with the state; the per-step scratch is
// sized by the step itself. The neighbour lists are rebuilt at the next step.

namespace pbf {

std::uint32_t PbfSolver::addParticles(const std::vector<Eigen::Vector3f>& positions,
                                      const std::vector<Eigen::Vector3f>& velocities) {
  if (velocities.size() != positions.size())
    throw std::invalid_argument("addParticles: " + std::to_string(velocities.size()) +
                                " velocities for " + std::to_string(positions.size()) + " positions");
  for (std::size_t i = 0; i < positions.size(); ++i)
    if (!positions[i].allFinite() || !velocities[i].allFinite())
      throw std::invalid_argument("addParticles: particle " + std::to_string(i) +
                                  " has a non-finite position or velocity");
  const std::uint64_t last = std::uint64_t(next_id_) + positions.size();
  if (last > std::numeric_limits<std::uint32_t>::max())
    throw std::invalid_argument("addParticles: particle ids are used up in this run (" +
                                std::to_string(next_id_) + " given); reset the fluid");
  const std::uint32_t first = next_id_;
  const std::size_t n = size() + positions.size();
  position_.insert(position_.end(), positions.begin(), positions.end());
  velocity_.insert(velocity_.end(), velocities.begin(), velocities.end());
  for (std::size_t i = 0; i < positions.size(); ++i) id_.push_back(next_id_++);
  // Until the next step measures them: at rest density, no neighbours counted yet.
  density_.resize(n, params_.rest_density);
  neighbor_count_.resize(n, 0);
  predicted_.resize(n, Eigen::Vector3f::Zero());
  delta_.resize(n, Eigen::Vector3f::Zero());
  new_velocity_.resize(n, Eigen::Vector3f::Zero());
  lambda_.resize(n, 0.0f);
  lambda_sum_.resize(n, 0.0f);  // no pressure of their own yet: the first solve gives it
  surface_lend_.resize(n, FreeSurfaceLend::kUnmeasured);  // nor a lend: measured by the next step
  lists_valid_ = false;
  return first;
}

std::size_t PbfSolver::removeParticles(const std::vector<std::uint8_t>& remove) {
  if (remove.size() != size())
    throw std::invalid_argument("removeParticles: " + std::to_string(remove.size()) +
                                " flags for " + std::to_string(size()) + " particles");
  // Stable compaction: the survivors keep their (Morton) order and their ids.
  std::size_t kept = 0;
  for (std::size_t i = 0; i < remove.size(); ++i) {
    if (remove[i]) continue;
    if (kept != i) {
      position_[kept] = position_[i];
      velocity_[kept] = velocity_[i];
      id_[kept] = id_[i];
      density_[kept] = density_[i];
      neighbor_count_[kept] = neighbor_count_[i];
      lambda_sum_[kept] = lambda_sum_[i];
      surface_lend_[kept] = surface_lend_[i];
    }
    ++kept;
  }
  const std::size_t removed = size() - kept;
  if (removed == 0) return 0;
  position_.resize(kept);
  velocity_.resize(kept);
  id_.resize(kept);
  density_.resize(kept);
  neighbor_count_.resize(kept);
  predicted_.resize(kept);
  delta_.resize(kept);
  new_velocity_.resize(kept);
  lambda_.resize(kept);
  lambda_sum_.resize(kept);
  surface_lend_.resize(kept);
  lists_valid_ = false;
  return removed;
}

}  // namespace pbf
