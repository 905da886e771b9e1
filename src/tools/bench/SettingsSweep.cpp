#include "bench/SettingsSweep.h"

#include <cstdio>
#include <functional>
#include <map>

#include "bench/BenchScenes.h"
#include "bench/CsvWriter.h"
#include "bench/DamBreak.h"
#include "bench/Hydrostatic.h"
#include "bench/Progress.h"

namespace pbf_bench {

namespace {

// Depth of the dam-break slab used in the sweep (see DamBreakStudy: uniform across y).
constexpr float kSweepDepth = 0.2f;
constexpr float kSweepSpacing = 0.02f;

struct Setting {
  std::string name, group;
  std::function<void(pbf::SolverParams&)> apply;
  float spacing = kSweepSpacing;
};

void fixedIterations(pbf::SolverParams& p, int n) {
  p.min_iterations = p.max_iterations = n;
  p.density_tolerance = 0.0f;
}
void tolerance(pbf::SolverParams& p, float tol, int max_iter = 30, int min_iter = 1) {
  p.min_iterations = min_iter;
  p.max_iterations = max_iter;
  p.density_tolerance = tol;
}
void fixedDt(pbf::SolverParams& p, float dt) {
  p.adaptive_time_step = false;
  p.time_step = dt;
}
void cfl(pbf::SolverParams& p, float factor, float max_dt) {
  p.adaptive_time_step = true;
  p.cfl_factor = factor;
  p.max_time_step = max_dt;
}

std::vector<Setting> settings(bool quick) {
  std::vector<Setting> s;
  auto add = [&s](std::string name, std::string group, std::function<void(pbf::SolverParams&)> f,
                  float spacing = kSweepSpacing) { s.push_back({std::move(name), std::move(group), std::move(f), spacing}); };
  const std::vector<int> iterations = quick ? std::vector<int>{1, 4, 12} : std::vector<int>{1, 2, 3, 4, 6, 8, 12, 20};
  for (int n : iterations)
    add("iter" + std::to_string(n), "iterations", [n](pbf::SolverParams& p) { fixedIterations(p, n); });
  const std::vector<float> tolerances = quick ? std::vector<float>{0.01f, 0.002f}
                                              : std::vector<float>{0.02f, 0.01f, 0.005f, 0.002f, 0.001f};
  for (float t : tolerances) {
    char name[32];
    std::snprintf(name, sizeof name, "tol%g", t);
    add(name, "tolerance", [t](pbf::SolverParams& p) { tolerance(p, t); });
  }
  if (quick) return s;
  // Time stepping, 4 iterations: fixed dt (CFL off) and CFL factors with a longer max dt.
  for (int hz : {60, 120, 240, 480})
    add("dt1/" + std::to_string(hz) + "_iter4", "fixed_dt", [hz](pbf::SolverParams& p) {
      fixedIterations(p, 4);
      fixedDt(p, 1.0f / hz);
    });
  add("cfl0.8_max1/60_iter4", "cfl", [](pbf::SolverParams& p) { fixedIterations(p, 4); cfl(p, 0.8f, 1.0f / 60); });
  add("cfl0.4_max1/60_iter4", "cfl", [](pbf::SolverParams& p) { fixedIterations(p, 4); cfl(p, 0.4f, 1.0f / 60); });
  add("cfl0.2_max1/120_iter4", "cfl", [](pbf::SolverParams& p) { fixedIterations(p, 4); cfl(p, 0.2f, 1.0f / 120); });
  // Combinations near the expected front: fewer iterations on a shorter step, tolerance
  // with a longer step.
  add("dt1/240_iter2", "combo", [](pbf::SolverParams& p) { fixedIterations(p, 2); fixedDt(p, 1.0f / 240); });
  add("cfl0.4_iter2", "combo", [](pbf::SolverParams& p) { fixedIterations(p, 2); });
  add("cfl0.8_max1/60_tol0.005", "combo", [](pbf::SolverParams& p) { tolerance(p, 0.005f); cfl(p, 0.8f, 1.0f / 60); });
  add("cfl0.4_tol0.005_max8", "combo", [](pbf::SolverParams& p) { tolerance(p, 0.005f, 8); });
  add("cfl0.4_tol0.002_max8", "combo", [](pbf::SolverParams& p) { tolerance(p, 0.002f, 8); });
  add("dt1/240_iter3", "combo", [](pbf::SolverParams& p) { fixedIterations(p, 3); fixedDt(p, 1.0f / 240); });
  add("dt1/240_tol0.005", "combo", [](pbf::SolverParams& p) { tolerance(p, 0.005f); fixedDt(p, 1.0f / 240); });
  add("cfl0.4_max1/240_iter4", "combo", [](pbf::SolverParams& p) { fixedIterations(p, 4); cfl(p, 0.4f, 1.0f / 240); });
  // Candidates for the shipped defaults: CFL with a shorter max dt (the hydrostatic error
  // is set by the resting step g dt^2) and a few iterations or a tolerance.
  add("cfl0.4_max1/360_iter4", "combo", [](pbf::SolverParams& p) { fixedIterations(p, 4); cfl(p, 0.4f, 1.0f / 360); });
  add("cfl0.4_max1/240_iter6", "combo", [](pbf::SolverParams& p) { fixedIterations(p, 6); cfl(p, 0.4f, 1.0f / 240); });
  add("cfl0.4_max1/240_tol0.003", "combo", [](pbf::SolverParams& p) { tolerance(p, 0.003f); cfl(p, 0.4f, 1.0f / 240); });
  add("cfl0.4_max1/180_tol0.003", "combo", [](pbf::SolverParams& p) { tolerance(p, 0.003f); cfl(p, 0.4f, 1.0f / 180); });
  // The shipped defaults (Gauss-Seidel sweeps to 0.3 %, at least one, at most 100).
  add("shipped", "combo", [](pbf::SolverParams&) {});
  add("cfl0.2_max1/480_tol0.003", "combo", [](pbf::SolverParams& p) { tolerance(p, 0.003f); cfl(p, 0.2f, 1.0f / 480); });
  // The Jacobi solve (shipped until session 21) beside it: fixed counts, and its tolerance
  // settings with at least two corrections per step (a single Jacobi correction overshoots
  // where corrections overlap; the half-dt pair shows it).
  auto jacobi = [](std::function<void(pbf::SolverParams&)> f) {
    return [f](pbf::SolverParams& p) {
      p.gauss_seidel = false;
      f(p);
    };
  };
  for (int n : {2, 4, 8})
    add("jacobi_iter" + std::to_string(n), "jacobi", jacobi([n](pbf::SolverParams& p) { fixedIterations(p, n); }));
  add("jacobi_cfl0.4_max1/240_tol0.003_min2", "jacobi",
      jacobi([](pbf::SolverParams& p) { tolerance(p, 0.003f, 100, 2); cfl(p, 0.4f, 1.0f / 240); }));
  add("jacobi_cfl0.4_max1/240_tol0.001_min2", "jacobi",
      jacobi([](pbf::SolverParams& p) { tolerance(p, 0.001f, 100, 2); cfl(p, 0.4f, 1.0f / 240); }));
  add("jacobi_cfl0.2_max1/480_tol0.003", "jacobi",
      jacobi([](pbf::SolverParams& p) { tolerance(p, 0.003f); cfl(p, 0.2f, 1.0f / 480); }));
  add("jacobi_cfl0.2_max1/480_tol0.003_min2", "jacobi",
      jacobi([](pbf::SolverParams& p) { tolerance(p, 0.003f, 100, 2); cfl(p, 0.2f, 1.0f / 480); }));
  // Resolution at the provisional defaults.
  add("d0.04", "resolution", [](pbf::SolverParams&) {}, 0.04f);
  add("d0.028", "resolution", [](pbf::SolverParams&) {}, 0.028f);
  return s;
}

// The converged reference of the dam break: many iterations, a small fixed dt.
void referenceSettings(pbf::SolverParams& p, bool quick) {
  fixedIterations(p, quick ? 12 : 20);
  fixedDt(p, quick ? 1.0f / 500 : 1.0f / 1000);
}

}  // namespace

void runSettingsSweep(const BenchOptions& o) {
  std::printf("\n== settings sweep: hydrostatic tank + dam break (Pareto data) ==\n");
  const FrontCurve martin_moyce = loadFrontCurve(o.reference_csv);
  const double settle = o.quick ? 0.6 : 1.5;

  // Every dam-break run starts from the same settled column (per spacing), so settings
  // differ only in how they run the collapse, not in how they digest the lattice.
  std::map<float, Positions> settled;
  auto startFor = [&](const pbf::Scene& scene) -> const Positions* {
    const float d = scene.solver.particle_spacing;
    if (!settled.count(d)) {
      Progress p("settling the column, d=" + std::to_string(d), o.progress);
      settled[d] = settledColumn(scene, &p);
    }
    return &settled[d];
  };
  pbf::Scene ref_scene = damBreakScene(o.scenes_dir, kSweepSpacing, kSweepDepth);
  referenceSettings(ref_scene.solver, o.quick);
  const Positions* ref_start = startFor(ref_scene);
  Progress ref_progress("dam break reference (converged)", o.progress);
  const DamBreakResult reference = runDamBreak(ref_scene, martin_moyce, &ref_progress, ref_start);
  ref_progress.done();
  std::printf("reference: %d iterations, dt %.4f s: RMS %.3f a (shift %.2f: %.3f a)\n",
              ref_scene.solver.max_iterations, ref_scene.solver.time_step, reference.rms_no_shift,
              reference.shift, reference.rms_shifted);

  CsvWriter csv(o.out_dir + "/sweep.csv",
                {"name", "group", "spacing", "min_iterations", "max_iterations", "density_tolerance",
                 "adaptive_time_step", "cfl_factor", "max_time_step", "time_step",
                 "hydro_particles", "hydro_wall_per_sim", "hydro_mean_iterations", "hydro_avg_err",
                 "hydro_max_err", "hydro_height_loss", "hydro_speed_max", "hydro_speed_rms",
                 "dam_particles", "dam_wall_per_sim", "dam_mean_iterations", "dam_rms_no_shift",
                 "dam_shift", "dam_rms_shifted", "dam_deviation", "hydro_cpu_per_sim", "dam_cpu_per_sim"});
  csv.row({std::string("reference"), std::string("reference"), double(kSweepSpacing),
           (long long)ref_scene.solver.min_iterations, (long long)ref_scene.solver.max_iterations, 0.0,
           0LL, 0.0, 0.0, double(ref_scene.solver.time_step), 0LL, NAN, NAN, NAN, NAN, NAN, NAN, NAN,
           (long long)reference.particles, reference.totals.wallPerSimSecond(),
           double(reference.totals.iterations) / std::max(1LL, reference.totals.steps),
           reference.rms_no_shift, reference.shift, reference.rms_shifted, 0.0, NAN,
           reference.totals.cpuPerSimSecond()});

  std::printf("%-26s %8s %8s %8s %8s %8s | %8s %8s %8s %8s\n", "setting", "h.wall/s", "avgErr%",
              "maxErr%", "loss%", "v_res", "d.wall/s", "RMS", "RMSsh", "dev");
  for (const Setting& s : settings(o.quick)) {
    pbf::Scene hydro = hydrostaticScene(o.scenes_dir, s.spacing);
    s.apply(hydro.solver);
    pbf::Scene dam = damBreakScene(o.scenes_dir, s.spacing, kSweepDepth);
    s.apply(dam.solver);
    Progress hp("hydrostatic " + s.name, o.progress);
    const HydrostaticResult h = runHydrostatic(hydro, settle, &hp);
    hp.done();
    const Positions* start = startFor(dam);
    Progress dp("dam break " + s.name, o.progress);
    const DamBreakResult d = runDamBreak(dam, martin_moyce, &dp, start);
    dp.done();
    const double deviation = profileDeviation(d, reference);
    const pbf::SolverParams& p = dam.solver;
    csv.row({s.name, s.group, double(s.spacing), (long long)p.min_iterations, (long long)p.max_iterations,
             double(p.density_tolerance), (long long)p.adaptive_time_step, double(p.cfl_factor),
             double(p.max_time_step), double(p.time_step), (long long)h.particles,
             h.totals.wallPerSimSecond(), h.mean_iterations, h.avg_density_error, h.max_density_error,
             h.height_loss, h.residual_speed_max, h.residual_speed_rms, (long long)d.particles,
             d.totals.wallPerSimSecond(), double(d.totals.iterations) / std::max(1LL, d.totals.steps),
             d.rms_no_shift, d.shift, d.rms_shifted, deviation, h.totals.cpuPerSimSecond(),
             d.totals.cpuPerSimSecond()});
    std::printf("%-26s %8.2f %8.3f %8.3f %8.2f %8.4f | %8.1f %8.3f %8.3f %8.3f%s\n", s.name.c_str(),
                h.totals.wallPerSimSecond(), 100 * h.avg_density_error, 100 * h.max_density_error,
                100 * h.height_loss, h.residual_speed_max, d.totals.wallPerSimSecond(), d.rms_no_shift,
                d.rms_shifted, deviation, (h.totals.failed || d.totals.failed) ? "  (a step FAILED)" : "");
    std::fflush(stdout);
  }
}

}  // namespace pbf_bench
