#include "bench/DamBreak.h"

#include <cmath>

#include "bench/BenchScenes.h"
#include "bench/Progress.h"
#include "bench/SurfaceMetrics.h"

namespace pbf_bench {

const std::vector<double>& profileTimes() {
  static const std::vector<double> t = {1.0, 2.0, 3.0};
  return t;
}

Positions settledColumn(const pbf::Scene& scene, Progress* progress) {
  pbf::Scene column = scene;
  column.container.max().x() = scene.fluid.at(0).max.x();
  column.solver.adaptive_time_step = false;
  column.solver.time_step = 1.0f / 240.0f;
  column.solver.min_iterations = 2;
  column.solver.max_iterations = 50;
  column.solver.density_tolerance = 0.0005f;
  auto solver = makeSolver(column);
  const int steps = 120;
  for (int k = 0; k < steps; ++k) {
    solver->step();
    const Positions x = solver->positions();
    solver->setParticles(x);  // zero velocities: relax towards equilibrium, no oscillation
    if (progress) progress->update(double(k + 1) / steps, "settling the column");
  }
  return solver->positions();
}

DamBreakResult runDamBreak(const pbf::Scene& scene, const FrontCurve& reference,
                           Progress* progress, const Positions* start) {
  DamBreakResult r;
  auto solver = makeSolver(scene);
  if (start) solver->setParticles(*start);
  r.particles = solver->size();
  r.a = damBreakWidth(scene);
  const double g = scene.solver.gravity.norm();
  const double t_scale = std::sqrt(2.0 * g / r.a);  // T = t * t_scale
  const float d = scene.solver.particle_spacing;
  const double bin = r.a / 10.0;
  std::size_t next_profile = 0;
  FrontCurve quarter_row, full_row;
  auto record = [&](const pbf::PbfSolver& s) {
    const double T = s.time() * t_scale;
    r.curve.T.push_back(T);
    r.curve.Z.push_back(surgeFront(s.positions(), d, scene.container) / r.a);
    quarter_row.T.push_back(T);
    quarter_row.Z.push_back(surgeFront(s.positions(), d, scene.container, 0.25) / r.a);
    full_row.T.push_back(T);
    full_row.Z.push_back(surgeFront(s.positions(), d, scene.container, 1.0) / r.a);
    r.curve_sliding.T.push_back(T);
    r.curve_sliding.Z.push_back(surgeFrontSliding(s.positions(), d, scene.container) / r.a);
    if (next_profile < profileTimes().size() && T >= profileTimes()[next_profile] - 1e-9) {
      std::vector<double> h = heightProfile(s.positions(), d, scene.container, bin);
      for (double& v : h) v /= r.a;
      r.profiles.push_back(std::move(h));
      ++next_profile;
    }
  };
  record(*solver);
  r.totals = runUntil(*solver, kDamBreakTEnd / t_scale,
                      [&](const pbf::PbfSolver& s, const pbf::StepStats&) { record(s); }, progress);
  r.rms_no_shift = frontRms(r.curve, reference, 0.0, kFrontRmsTMax);
  r.shift = bestShift(r.curve, reference, kFrontRmsTMax, kMaxGateShift);
  r.rms_shifted = frontRms(r.curve, reference, r.shift, kFrontRmsTMax);
  r.rms_no_shift_quarter_row = frontRms(quarter_row, reference, 0.0, kFrontRmsTMax);
  r.rms_no_shift_full_row = frontRms(full_row, reference, 0.0, kFrontRmsTMax);
  r.shift_quarter_row = bestShift(quarter_row, reference, kFrontRmsTMax, kMaxGateShift);
  r.shift_full_row = bestShift(full_row, reference, kFrontRmsTMax, kMaxGateShift);
  r.rms_no_shift_sliding = frontRms(r.curve_sliding, reference, 0.0, kFrontRmsTMax);
  r.shift_sliding = bestShift(r.curve_sliding, reference, kFrontRmsTMax, kMaxGateShift);
  r.rms_shifted_sliding = frontRms(r.curve_sliding, reference, r.shift_sliding, kFrontRmsTMax);
  return r;
}

double profileDeviation(const DamBreakResult& run, const DamBreakResult& ref) {
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t k = 0; k < std::min(run.profiles.size(), ref.profiles.size()); ++k)
    for (std::size_t i = 0; i < std::min(run.profiles[k].size(), ref.profiles[k].size()); ++i) {
      // Only where either run has fluid: empty tank length would dilute the figure.
      if (run.profiles[k][i] <= 0.0 && ref.profiles[k][i] <= 0.0) continue;
      const double e = run.profiles[k][i] - ref.profiles[k][i];
      sum += e * e;
      ++n;
    }
  return n ? std::sqrt(sum / n) : NAN;
}

}  // namespace pbf_bench
