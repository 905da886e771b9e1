#include "pbf_ros/core/PbfSolver.h"

#include <omp.h>

#include <algorithm>
#include <cmath>

#include "ContainerMirror.h"
#include "NeighborSums.h"
#include "PackedSlots.h"
#include "PairGeometry.h"
#include "pbf_ros/core/Boundaries.h"
#include "pbf_ros/core/Kernels.h"
#include "pbf_ros/core/NeighborGrid.h"

// The velocity-level passes that follow the constraint solve: velocities from the corrected
// positions (with wall friction), density and vorticity, XSPH viscosity and confinement.

namespace pbf {

namespace {

// sum over neighbours j within h of term(j, V_j grad_i W_ij), V_j = m / rho_j: the SPH
// gradient-weighted sums of the vorticity passes (curl of v, gradient of |omega|).
template <typename Term>
Eigen::Vector3f sumVolumeGradients(const Kernels& k, float mass, std::size_t i,
                                   const std::vector<Eigen::Vector3f>& position,
                                   const std::vector<float>& density,
                                   const std::vector<std::uint32_t>& id,
                                   const std::vector<std::uint32_t>& off,
                                   const std::vector<std::uint32_t>& nbr, Term term) {
  Eigen::Vector3f sum = Eigen::Vector3f::Zero();
  for (std::uint32_t e = off[i]; e < off[i + 1]; ++e) {
    const std::uint32_t j = nbr[e];
    Pair p;
    p.r = position[i] - position[j];
    p.r2 = p.r.squaredNorm();
    if (p.r2 >= k.h2) continue;
    p.rlen = std::sqrt(p.r2);
    sum += term(j, Eigen::Vector3f((mass / density[j]) * spikyGradientSafe(k, p, id[i], id[j])));
  }
  return sum;
}

}  // namespace

bool PbfSolver::updateVelocities(float dt) {
  const std::size_t n = size();
  const float inv_dt = 1.0f / dt;
  const SolidBoundaries solids = boundaries();
  const float friction = params_.wall_friction;
  const float layer = params_.particle_spacing;
  // `report(solid, point, displacement)` hears what each solid does to the particle (wrench
  // tracking); a no-op otherwise, which the compiler removes.
  auto settle = [&](std::size_t i, auto&& report) {
    // With zero iterations the prediction itself may have left the box.
    Eigen::Vector3f p = solids.project(predicted_[i], report);
    Eigen::Vector3f normal, surface_motion;
    int solid = 0;
    if (friction > 0.0f && solids.contact(p, layer, normal, surface_motion, &solid)) {
      // Wall shear tau = rho0 c_f |u_t| u_t acts on the layer of thickness d next to the
      // surface: du_t/dt = -c_f |u_t| u_t / d. Backward Euler over the step gives
      // u_t' = u_t / (1 + c_f |u_t| dt / d), in displacements (t = u_t dt) below: stable at
      // any dt and converging to the same law as dt shrinks. The normal part of the motion
      // is the projection's business.
      const Eigen::Vector3f rel = (p - position_[i]) - surface_motion;
      const Eigen::Vector3f tangential = rel - rel.dot(normal) * normal;
      const float keep = 1.0f / (1.0f + friction * tangential.norm() / layer);
      const Eigen::Vector3f drag = -(1.0f - keep) * tangential;
      report(solid, p, drag);
      p += drag;
      p = solids.project(p, report);
    }
    velocity_[i] = (p - position_[i]) * inv_dt;
    position_[i] = p;
    return p != predicted_[i];
  };
  bool moved = false;
  if (!track_wrenches_) {
#pragma omp parallel for schedule(static) reduction(|| : moved)
    for (std::size_t i = 0; i < n; ++i)
      moved = settle(i, [](int, const Eigen::Vector3f&, const Eigen::Vector3f&) {}) || moved;
    return moved;
  }
#pragma omp parallel reduction(|| : moved)
  {
    const int thread = omp_get_thread_num();
#pragma omp for schedule(static)
    for (std::size_t i = 0; i < n; ++i)
      moved = settle(i, [&](int s, const Eigen::Vector3f& x, const Eigen::Vector3f& dx) {
                wrench_sums_.add(thread, s, x, dx);
              }) || moved;
  }
  return moved;
}

const float* PbfSolver::computeDensityAndVorticity(bool density_known) {
  const std::size_t n = size();
  const Kernels k(params_.supportRadius());
  const auto& off = grid_->offsets();
  const auto& nbr = grid_->indices();
  const float mass = params_.particleMass();  // SPH volumes m / rho_j (vorticity)
  const bool vorticity = params_.vorticity_epsilon > 0.0f;
  if (vorticity) vorticity_.resize(n);
  const NeighborArrays arrays{position_.empty() ? nullptr : position_[0].data(), off.data(), nbr.data(),
                             density_known ? nullptr : packed_->packPositions(position_)};

  // Density first (vorticity needs every density).
  if (!density_known) measureDensity(position_, arrays.packed);
  if (!vorticity) return arrays.packed;
  // omega_i = sum_j V_j grad_i W_ij x (v_j - v_i): the SPH curl of the velocity.
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3f vi = velocity_[i];
    vorticity_[i] = sumVolumeGradients(
        k, mass, i, position_, density_, id_, off, nbr,
        [&](std::uint32_t j, const Eigen::Vector3f& vgrad) { return vgrad.cross(velocity_[j] - vi); });
  }
  return arrays.packed;
}

void PbfSolver::applyViscosityAndVorticity(float dt, const float* packed_positions) {
  const std::size_t n = size();
  const Kernels k(params_.supportRadius());
  const auto& off = grid_->offsets();
  const auto& nbr = grid_->indices();
  const float mass = params_.particleMass();
  const float c = params_.xsphCoefficient(dt);
  const bool vorticity = params_.vorticity_epsilon > 0.0f;
  const float veps = params_.vorticity_epsilon * k.h;  // f = epsilon h (N x omega)

  const bool xsph = c > 0.0f;
  // The density pass packed the positions unless the solve had measured the density.
  const float* packed = nullptr;
  if (xsph) packed = packed_positions != nullptr ? packed_positions : packed_->packPositions(position_);
  const NeighborArrays arrays{position_.empty() ? nullptr : position_[0].data(), off.data(), nbr.data(),
                             packed};
  const PairConstants pc{k.h, k.h2, mass * k.poly6_coef, 0.0f, 0.0f, 0.0f};
  const float* V = velocity_.empty() ? nullptr : velocity_[0].data();
  const float* velocity_slots = xsph ? packed_->packVelocities(velocity_, density_) : nullptr;
  if (vorticity) {  // |omega| once per particle, not once per pair
    vorticity_norm_.resize(n);
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) vorticity_norm_[i] = vorticity_[i].norm();
  }

#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    Eigen::Vector3f v = velocity_[i];
    if (xsph) {  // XSPH (eq 10) with the m_j / rho_j factor
      const VectorSum s = xsphSums(arrays, pc, i, V, density_.data(), velocity_slots);
      v += c * Eigen::Vector3f(s.x, s.y, s.z);
    }
    if (vorticity) {
      // eta = grad |omega|, SPH difference form (exact for a constant field).
      const float wi = vorticity_norm_[i];
      const Eigen::Vector3f eta = sumVolumeGradients(
          k, mass, i, position_, density_, id_, off, nbr,
          [&](std::uint32_t j, const Eigen::Vector3f& vgrad) { return (vorticity_norm_[j] - wi) * vgrad; });
      const float eta_len = eta.norm();
      // No gradient, no direction: confinement has nothing to amplify there.
      if (eta_len > 1e-12f) v += (dt * veps) * (eta / eta_len).cross(vorticity_[i]);
    }
    new_velocity_[i] = v;
  }
  velocity_.swap(new_velocity_);
}

}  // namespace pbf
