#include "bench/EnergyBound.h"

#include <algorithm>
#include <cmath>

namespace pbf_bench {

EnergyBound energyBound(const std::vector<Eigen::Vector3f>& positions,
                        const std::vector<Eigen::Vector3f>& velocities,
                        const pbf::SolverParams& params, const Eigen::AlignedBox3f& container) {
  EnergyBound b;
  const double m = params.particleMass();
  // Gravity as the solver's speed cap sees it (never below 1 g), pointing down z.
  const double g = std::max<double>(params.gravity.norm(), 9.81);
  const float half = 0.5f * params.particle_spacing;
  const Eigen::Vector3f lo = container.min() + Eigen::Vector3f::Constant(half);
  const Eigen::Vector3f hi = container.max() - Eigen::Vector3f::Constant(half);
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const Eigen::Vector3f p = positions[i].cwiseMax(lo).cwiseMin(hi);
    b.initial_potential += m * g * (p.z() - lo.z());
    if (i < velocities.size()) b.initial_kinetic += 0.5 * m * velocities[i].squaredNorm();
  }
  const double n = static_cast<double>(positions.size());
  b.overlap_allowance = n * m * g * container.sizes().z();
  const double cap = params.max_speed_factor * std::sqrt(2.0 * g * container.sizes().maxCoeff());
  // The solver caps in float: a capped speed may sit an ulp (~1e-7) above this exact value.
  b.speed_cap_bound = 0.5 * n * m * cap * cap * (1.0 + 1e-6);
  return b;
}

double bodiesAllowance(const pbf::FloatingBodies& bodies, const pbf::SolverParams& params,
                       const Eigen::AlignedBox3f& container) {
  const double g = std::max<double>(params.gravity.norm(), 9.81);
  double allowance = 0.0;
  for (const auto& [index, body] : bodies.bodies()) {
    const pbf::Obstacle& o = body.shape();
    double lowest = 0.0;  // how far below its centre the body reaches, at least
    if (o.shape == pbf::Obstacle::Shape::Sphere) lowest = o.radius;
    if (o.shape == pbf::Obstacle::Shape::Box) lowest = o.half_extents.minCoeff();
    const double drop = std::max(0.0, double(o.pose.translation().z()) - (container.min().z() + lowest));
    allowance += body.kineticEnergy() + body.mass() * g * drop;
  }
  return allowance;
}

}  // namespace pbf_bench
