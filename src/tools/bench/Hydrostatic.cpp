#include "bench/Hydrostatic.h"

#include <algorithm>
#include <cmath>

#include "pbf_ros/core/Metrics.h"

namespace pbf_bench {

namespace {

// The first layer's density by how many walls it touches, and how close it stays to each
// wall (HydrostaticResult). The top of the container is left out: the water never reaches it.
void measureWallLayers(const pbf::PbfSolver& solver, const pbf::Scene& scene, double surface,
                       HydrostaticResult& r) {
  const float d = scene.solver.particle_spacing;
  // Within h of the free surface a particle's sum is truncated by the air, not the wall.
  const double below = surface - scene.solver.supportRadius();
  const Eigen::AlignedBox3f& box = scene.container;
  const auto& x = solver.positions();
  const auto& rho = solver.densities();
  double sum[4] = {0, 0, 0, 0};
  long long count[4] = {0, 0, 0, 0};
  double floor_sum[3] = {0, 0, 0};  // on the floor by 0 or 1 side wall; second layer inside
  long long floor_n[3] = {0, 0, 0};
  constexpr int kWalls = 5;  // x-, x+, y-, y+, floor
  double gap_sum[kWalls] = {0, 0, 0, 0, 0};
  long long gap_n[kWalls] = {0, 0, 0, 0, 0};
  for (std::size_t i = 0; i < x.size(); ++i) {
    const float dist[kWalls] = {x[i].x() - box.min().x(), box.max().x() - x[i].x(), x[i].y() - box.min().y(),
                                box.max().y() - x[i].y(), x[i].z() - box.min().z()};
    int touching = 0;
    for (int w = 0; w < kWalls; ++w) {
      if (dist[w] >= d) continue;
      ++touching;
      gap_sum[w] += dist[w] / d;
      ++gap_n[w];
    }
    if (x[i].z() > below) continue;
    sum[std::min(touching, 3)] += rho[i] / scene.solver.rest_density;
    ++count[std::min(touching, 3)];
    // floor_sum's slot: 0 the floor's first layer, 1 a bottom edge, 2 the second layer inside.
    const bool on_floor = dist[kWalls - 1] < d;
    int at_floor = -1;
    if (on_floor && touching <= 2) at_floor = touching - 1;  // the floor and 0 or 1 side wall
    else if (touching == 0 && dist[kWalls - 1] < 2.0f * d) at_floor = 2;
    if (at_floor >= 0) {
      floor_sum[at_floor] += rho[i] / scene.solver.rest_density;
      ++floor_n[at_floor];
    }
  }
  auto mean = [](double total, long long n) { return n ? total / n : NAN; };
  r.interior_density = mean(sum[0], count[0]);
  r.face_density = mean(sum[1], count[1]);
  r.edge_density = mean(sum[2], count[2]);
  r.corner_density = mean(sum[3], count[3]);
  r.floor_density = mean(floor_sum[0], floor_n[0]);
  r.bottom_edge_density = mean(floor_sum[1], floor_n[1]);
  r.second_layer_inside_density = mean(floor_sum[2], floor_n[2]);
  r.wall_gap = 0.0;
  for (int w = 0; w < kWalls; ++w)
    r.wall_gap = std::max(r.wall_gap, gap_n[w] ? gap_sum[w] / gap_n[w] : INFINITY);
}

// HydrostaticResult::bulk_number_density. The region's faces lie on whole spacings from the
// container's floor and side walls, where the tank's water starts, so they fall between the
// lattice's planes and the start lattice counts exactly one particle per d^3.
double bulkNumberDensity(const pbf::PbfSolver& solver, const pbf::Scene& scene, double surface) {
  const double d = scene.solver.particle_spacing;
  const Eigen::Vector3d lo = scene.container.min().cast<double>() + Eigen::Vector3d::Constant(2.0 * d);
  Eigen::Vector3d hi = scene.container.max().cast<double>() - Eigen::Vector3d::Constant(2.0 * d);
  hi.z() = scene.container.min().z() + std::floor((surface - scene.solver.supportRadius()) / d) * d;
  if (!(hi.array() > lo.array()).all()) return NAN;
  std::size_t inside = 0;
  for (const auto& x : solver.positions()) {
    const Eigen::Vector3d p = x.cast<double>();
    if ((p.array() > lo.array()).all() && (p.array() < hi.array()).all()) ++inside;
  }
  return inside * d * d * d / (hi - lo).prod();
}

}  // namespace

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
                        if (s.time() <= kStartupSeconds + 1e-9)
                          for (const auto& v : s.velocities())
                            r.startup_speed_max = std::max(r.startup_speed_max, double(v.norm()));
                        if (s.time() <= kFirstStepsSeconds + 1e-9)
                          r.first_steps_speed_max = r.startup_speed_max;
                        if (s.time() < window_start) return;
                        err_sum += st.avg_density_error;
                        ++err_n;
                        r.max_density_error = std::max(r.max_density_error, st.max_density_error);
                      },
                      progress);
  r.avg_density_error = err_n ? err_sum / err_n : NAN;
  const double surface = pbf::freeSurfaceHeight(solver->positions(), d, scene.container);
  r.height_loss = (h_volume - surface) / h_volume;
  r.mean_height_loss = 1.0 - 2.0 * pbf::meanHeightAboveFloor(solver->positions(), scene.container) / h_volume;
  measureWallLayers(*solver, scene, surface, r);
  r.bulk_number_density = bulkNumberDensity(*solver, scene, surface);
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
