#include "bench/TankStudy.h"

#include <cstdio>
#include <string>
#include <vector>

#include "bench/BenchScenes.h"
#include "bench/CsvWriter.h"
#include "bench/Hydrostatic.h"
#include "bench/Progress.h"

namespace pbf_bench {

namespace {

struct TankRun {
  std::string label;
  float spacing;
  bool half_dt;  // CFL factor and max dt halved (the dam-break study's "dt halved")
};

}  // namespace

void runTankStudy(const BenchOptions& o) {
  std::printf("\n== hydrostatic tank: start-up, level, resolution and dt ==\n");
  if (!o.solver_overrides.empty()) std::printf("solver overrides:\n%s", o.solver_overrides.c_str());
  const double seconds = o.quick ? 0.6 : 1.5;  // as the settings sweep: level after 1.5 s
  const std::vector<TankRun> runs = {{"d=0.02", 0.02f, false},
                                     {"d=0.02, dt halved", 0.02f, true},
                                     {"d=0.0125", 0.0125f, false},
                                     {"d=0.0125, dt halved", 0.0125f, true},
                                     // Finer still, to see which figures shrink with d.
                                     {"d=0.01", 0.01f, false},
                                     {"d=0.00833", 0.3f / 36.0f, false}};
  CsvWriter csv(o.out_dir + "/tank.csv",
                {"run", "spacing", "particles", "startup_speed_max", "first_steps_speed_max", "height_loss",
                 "bulk_number_density", "avg_density_error",
                 "max_density_error", "interior_density", "face_density", "edge_density", "corner_density", "wall_gap",
                 "speed_rms_end", "mean_iterations", "steps", "wall_per_sim_s",
                 "floor_density", "bottom_edge_density", "second_layer_inside_density", "capped_steps",
                 "mean_height_loss"});
  std::printf("%-22s %9s %17s %12s %12s %10s %10s %32s %8s %9s\n", "run", "particles", "start-up max v",
              "first 0.05 s", "level loss", "bulk n d^3", "avg err", "rho/rho0 inside/face/edge/corner",
              "wall gap", "wall/sim");
  for (const TankRun& run : runs) {
    if (o.quick && run.spacing < 0.02f) continue;
    pbf::Scene scene = hydrostaticScene(o.scenes_dir, run.spacing);
    if (!o.solver_overrides.empty()) pbf::applySolverYaml(o.solver_overrides, "--set", scene.solver);
    if (run.half_dt) {
      scene.solver.cfl_factor *= 0.5f;
      scene.solver.max_time_step *= 0.5f;
      scene.solver.time_step *= 0.5f;
    }
    Progress progress("tank " + run.label, o.progress);
    const HydrostaticResult r = runHydrostatic(scene, seconds, &progress);
    progress.done();
    csv.row({run.label, double(run.spacing), (long long)r.particles, r.startup_speed_max, r.first_steps_speed_max,
             r.height_loss, r.bulk_number_density,
             r.avg_density_error, r.max_density_error, r.interior_density, r.face_density, r.edge_density, r.corner_density,
             r.wall_gap, r.residual_speed_rms, r.mean_iterations,
             r.totals.steps, r.totals.wallPerSimSecond(), r.floor_density, r.bottom_edge_density,
             r.second_layer_inside_density, r.totals.capped_steps, r.mean_height_loss});
    std::printf("%-22s %9zu %13.3f m/s %8.3f m/s %10.2f %% %10.4f %8.3f %% %.4f/%.4f/%.4f/%.4f %7.2f d %9.2f\n",
                run.label.c_str(), r.particles, r.startup_speed_max, r.first_steps_speed_max,
                100.0 * r.height_loss, r.bulk_number_density,
                100.0 * r.avg_density_error, r.interior_density, r.face_density, r.edge_density, r.corner_density, r.wall_gap, r.totals.wallPerSimSecond());
    std::printf("%-22s at the floor: first layer %.4f, bottom edges %.4f, corners %.4f, second layer inside %.4f\n",
                "", r.floor_density, r.bottom_edge_density, r.corner_density, r.second_layer_inside_density);
    std::printf("%-22s %.1f iterations per step, %lld of %lld steps stopped at max_iterations; level loss\n"
                "%-22s of the mean height (2 z_mean) %.2f %%\n", "",
                r.mean_iterations, r.totals.capped_steps, r.totals.steps, "", 100.0 * r.mean_height_loss);
    std::fflush(stdout);
  }
  std::printf("(start-up: largest particle speed over the first %.1f s, and over the first %.2f s; level\n"
              " loss = (level the volume implies - free surface) / that level after %.1f s, the free\n"
              " surface where the colour field falls to one half (pbf::freeSurfaceHeight); bulk n d^3:\n"
              " particles per d^3 at the end, 2 d from the walls and h below the surface (1 for the\n"
              " start lattice); errors averaged over the last third; at the end: mean density of the\n"
              " particles within d of no, one, two, three walls and h below the surface, and the first\n"
              " layer's largest mean distance from a wall)\n",
              kStartupSeconds, kFirstStepsSeconds, seconds);
}

}  // namespace pbf_bench
