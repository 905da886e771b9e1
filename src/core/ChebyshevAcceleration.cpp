#include "pbf_ros/core/ChebyshevAcceleration.h"

#include <algorithm>
#include <cmath>

#include "pbf_ros/core/Boundaries.h"

namespace pbf {

void ChebyshevAcceleration::begin(const std::vector<Eigen::Vector3f>& q0, float rho) {
  rho_ = rho;
  omega_ = 1.0f;
  omega_limit_ = 2.0f / (1.0f + std::sqrt(1.0f - rho * rho));
  since_start_ = 0;
  previous_.clear();
  if (isOn()) current_ = q0;
}

void ChebyshevAcceleration::extrapolate(std::vector<Eigen::Vector3f>& q,
                                        const SolidBoundaries& solids) {
  if (!isOn()) return;
  const float rho2 = rho_ * rho_;
  if (since_start_ < kPlainIterations)
    omega_ = 1.0f;
  else if (since_start_ == kPlainIterations)
    omega_ = 2.0f / (2.0f - rho2);
  else
    omega_ = 4.0f / (4.0f - rho2 * omega_);
  omega_ = std::min(omega_, omega_limit_);
  ++since_start_;
  const std::size_t n = q.size();
  if (omega_ != 1.0f && previous_.size() == n) {
    const float w = omega_;
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) q[i] = solids.project(previous_[i] + w * (q[i] - previous_[i]));
  }
  previous_.swap(current_);
  current_ = q;
}

void ChebyshevAcceleration::reorder(const std::vector<std::uint32_t>& order,
                                    std::vector<Eigen::Vector3f>& scratch) {
  for (std::vector<Eigen::Vector3f>* v : {&previous_, &current_}) {
    if (v->size() != order.size()) continue;
    scratch.resize(order.size());
#pragma omp parallel for schedule(static)
    for (std::size_t k = 0; k < order.size(); ++k) scratch[k] = (*v)[order[k]];
    v->swap(scratch);
  }
}

}  // namespace pbf
