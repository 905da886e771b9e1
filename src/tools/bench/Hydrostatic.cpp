#include "bench/Hydrostatic.h"

#include <algorithm>
#include <cmath>

#include "pbf_ros/core/Metrics.h"

namespace pbf_bench {

HydrostaticResult runHydrostatic(const pbf::Scene& scene, double settle_seconds, Progress* progress) {
  HydrostaticResult r;
  auto solver = makeSolver(scene);
  r.particles = solver->size();
  const float d = scene.solver.particle_spacing;
  // The level the particles' volume implies (N d^3 spread over the floor).
  const Eigen::Vector3f size = scene.container.sizes();
  const double h_volume = r.particles * double(d) * d * d / (double(size.x()) * size.y());
  const double window_start = settle_seconds * 2.0 / 3.0;
  double err_sum = 0.0;
  long long err_n = 0;
  r.totals = runUntil(*solver, settle_seconds,
                      [&](const pbf::PbfSolver& s, const pbf::StepStats& st) {
                        if (s.time() < window_start) return;
                        err_sum += st.avg_density_error;
                        ++err_n;
                        r.max_density_error = std::max(r.max_density_error, st.max_density_error);
                      },
                      progress);
  r.avg_density_error = err_n ? err_sum / err_n : NAN;
  r.height_loss = (h_volume - pbf::freeSurfaceHeight(solver->positions(), d, scene.container)) / h_volume;
  double v2 = 0.0, vmax2 = 0.0;
  for (const auto& v : solver->velocities()) {
    v2 += v.squaredNorm();
    vmax2 = std::max(vmax2, double(v.squaredNorm()));
  }
  r.residual_speed_max = std::sqrt(vmax2);
  r.residual_speed_rms = std::sqrt(v2 / std::max<std::size_t>(1, r.particles));
  r.mean_iterations = r.totals.steps ? double(r.totals.iterations) / r.totals.steps : 0.0;
  return r;
}

}  // namespace pbf_bench
