// pbf_bench: the proof that the solver is accurate and fast (issue 5). No ROS.
//
//   pbf_bench [--out DIR] [--only dambreak,sweep,scaling,warmstart,tank,convergence] [--quick] [--threads N]
//             [--reference CSV] [--scenes-dir DIR] [--no-progress] [--set key=value]...
//
// Studies (each writes CSV files into DIR; scripts/plot_bench.py turns them into PNGs):
//   dambreak  surge front Z(T) against Martin & Moyce (1952) at three resolutions and for
//             the shipped scene            -> dambreak_front.csv, dambreak_summary.csv
//   sweep     solver settings on the hydrostatic tank and the dam break: density error,
//             level loss, residual speed, front RMS, deviation from a converged run, and
//             wall seconds per simulated second (hydrostatic study + Pareto) -> sweep.csv
//   scaling   ms per step against particles (10k..320k) and threads -> scaling.csv
//   warmstart iterations to 0.1 % / 0.01 % density error with and without the warm start,
//             at dt 1/240, 1/120, 1/60 s, hydrostatic tank and dam break -> warm_start.csv
//   tank      the hydrostatic tank's start-up speed, level, density error and first layers
//             along the walls at d = 0.02 and 0.0125 m, each also with dt halved, and at
//             d = 0.01 and 0.00833 m -> tank.csv
//   convergence  (only when named in --only: ~10 min) the dam-break slab at a/d = 10 ... 64
//             -> dambreak_convergence_front.csv, dambreak_convergence_summary.csv
// --quick runs smaller, shorter versions of each (for checking the pipeline, not figures).
// --set overrides a solver parameter in the dam-break and tank studies (e.g. proposed defaults).

#include <omp.h>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>

#include "bench/BenchOptions.h"
#include "bench/BenchScenes.h"
#include "bench/DamBreakStudy.h"
#include "bench/ScalingStudy.h"
#include "bench/SettingsSweep.h"
#include "bench/TankStudy.h"
#include "bench/WarmStartStudy.h"

namespace {

// Run by default (scripts/bench_all.sh), and the one that only runs when named.
const std::set<std::string> kStudies = {"dambreak", "sweep", "scaling", "warmstart", "tank"};
const std::string kOptionalStudy = "convergence";

void usage(std::ostream& out) {
  out << "usage: pbf_bench [--out DIR] [--only dambreak,sweep,scaling,warmstart,tank,convergence] [--quick]\n"
         "                 [--threads N] [--reference CSV] [--scenes-dir DIR] [--no-progress] [--set key=value]...\n";
}

int parseInt(const std::string& option, const std::string& text) {
  std::size_t used = 0;
  int v = 0;
  try {
    v = std::stoi(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || text.empty())
    throw std::invalid_argument(option + " expects an integer, got '" + text + "'");
  return v;
}

}  // namespace

int main(int argc, char** argv) {
  pbf_bench::BenchOptions o;
  o.scenes_dir = pbf_bench::defaultScenesDir();
  // A copy of ../shared/reference/martin_moyce_1952_surge_front.csv, kept with the figures.
  o.reference_csv = std::string(PBF_SOURCE_DIR) + "/doc/validation/martin_moyce_1952_surge_front.csv";
  std::set<std::string> only = kStudies;
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      auto value = [&]() -> std::string {
        if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value");
        return argv[++i];
      };
      if (a == "--out") o.out_dir = value();
      else if (a == "--quick") o.quick = true;
      else if (a == "--no-progress") o.progress = false;
      else if (a == "--reference") o.reference_csv = value();
      else if (a == "--scenes-dir") o.scenes_dir = value();
      else if (a == "--set") {
        const std::string kv = value();
        const auto eq = kv.find('=');
        if (eq == std::string::npos || eq == 0)
          throw std::invalid_argument("--set expects key=value, got '" + kv + "'");
        o.solver_overrides += kv.substr(0, eq) + ": " + kv.substr(eq + 1) + "\n";
      }
      else if (a == "--threads") {
        o.threads = parseInt(a, value());
        if (o.threads < 1) throw std::invalid_argument("--threads must be >= 1");
      } else if (a == "--only") {
        only.clear();
        std::stringstream list(value());
        for (std::string s; std::getline(list, s, ',');) {
          if (!kStudies.count(s) && s != kOptionalStudy)
            throw std::invalid_argument("--only: unknown study '" + s + "' (known: dambreak, sweep, scaling, warmstart, tank, convergence)");
          only.insert(s);
        }
      } else if (a == "-h" || a == "--help") {
        usage(std::cout);
        return 0;
      } else {
        throw std::invalid_argument("unknown argument '" + a + "'");
      }
    }
  } catch (const std::exception& e) {
    std::cerr << "pbf_bench: " << e.what() << "\n";
    usage(std::cerr);
    return 2;
  }
  try {
    std::filesystem::create_directories(o.out_dir);
    if (!std::filesystem::exists(o.reference_csv))
      throw std::runtime_error("reference data not found: " + o.reference_csv + " (use --reference)");
    if (o.threads > 0) omp_set_num_threads(o.threads);
    std::printf("pbf_bench: output in %s%s, %d OpenMP threads\n", o.out_dir.c_str(),
                o.quick ? " (quick mode)" : "", omp_get_max_threads());
    if (only.count("dambreak")) pbf_bench::runDamBreakStudy(o);
    if (only.count("convergence")) pbf_bench::runDamBreakConvergence(o);
    if (only.count("sweep")) pbf_bench::runSettingsSweep(o);
    if (only.count("scaling")) pbf_bench::runScalingStudy(o);
    if (only.count("warmstart")) pbf_bench::runWarmStartStudy(o);
    if (only.count("tank")) pbf_bench::runTankStudy(o);
  } catch (const std::exception& e) {
    std::cerr << "\npbf_bench: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
