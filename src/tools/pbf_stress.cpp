// pbf_stress: the hostile-case matrix (issue 5). No ROS. Prints one row per case with
// pass/fail and writes stress.csv; exits 1 when any case fails.
//
//   pbf_stress [--out DIR] [--reduced] [--only SUBSTRING] [--list] [--no-progress]
//              [--set key=value]...
//
// Pass means: no NaN/Inf in any position, velocity or density; no particle outside the
// container; every step completed; kinetic energy bounded: E_kin <= E_kin,0 + E_pot,0 at
// every step, or for starts with overlapping particles E_kin <= 1/2 N m cap^2 at every step
// and <= E_kin,0 + E_pot,0 + N m g H at the end (bench/EnergyBound.h says why).
// --reduced is the short matrix ctest runs. With --out, stress_energy.csv holds E_kin(t).
// --set overrides a solver parameter in every case after it is built (e.g. warm_start=true):
// the same hostile situations for an option that is off by default. A case whose own
// settings the solver refuses with the overrides is reported SKIPPED, with the reason, and
// the others run (skipped cases are neither passes nor failures).

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>

#include "bench/CsvWriter.h"
#include "bench/Progress.h"
#include "bench/StressCases.h"
#include "pbf_ros/core/Scene.h"

namespace {

void usage(std::ostream& out) {
  out << "usage: pbf_stress [--out DIR] [--reduced] [--only SUBSTRING] [--list] [--no-progress]\n"
         "                  [--set key=value]...\n";
}

const char* mark(bool ok) { return ok ? "ok" : "FAIL"; }

}  // namespace

int main(int argc, char** argv) {
  std::string out_dir, only, overrides;
  bool reduced = false, list = false, progress = true;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::cerr << "pbf_stress: " << a << " needs a value\n";
        usage(std::cerr);
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--out") out_dir = value();
    else if (a == "--reduced") reduced = true;
    else if (a == "--only") only = value();
    else if (a == "--list") list = true;
    else if (a == "--no-progress") progress = false;
    else if (a == "--set") {
      const std::string kv = value();
      const std::size_t eq = kv.find('=');
      if (eq == std::string::npos || eq == 0) {
        std::cerr << "pbf_stress: --set expects key=value, got '" << kv << "'\n";
        return 2;
      }
      overrides += kv.substr(0, eq) + ": " + kv.substr(eq + 1) + "\n";
    }
    else if (a == "-h" || a == "--help") {
      usage(std::cout);
      return 0;
    } else {
      std::cerr << "pbf_stress: unknown argument '" << a << "'\n";
      usage(std::cerr);
      return 2;
    }
  }
  try {
    auto cases = pbf_bench::stressCases(reduced);
    if (!overrides.empty()) {
      pbf_bench::applySolverOverrides(cases, overrides);  // a bad key fails here, by name
      std::printf("pbf_stress: solver overrides in every case:\n%s", overrides.c_str());
    }
    if (list) {
      for (const auto& c : cases) std::printf("%-30s %s\n", c.name.c_str(), c.setup.c_str());
      return 0;
    }
    const bool any = std::any_of(cases.begin(), cases.end(), [&](const pbf_bench::StressCase& c) {
      return only.empty() || c.name.find(only) != std::string::npos;
    });
    if (!any) {
      std::cerr << "pbf_stress: no case matches '" << only << "' (see --list)\n";
      return 2;
    }
    std::unique_ptr<pbf_bench::CsvWriter> csv, energy;
    if (!out_dir.empty()) {
      std::filesystem::create_directories(out_dir);
      csv = std::make_unique<pbf_bench::CsvWriter>(
          out_dir + (reduced ? "/stress_reduced.csv" : "/stress.csv"),
          std::vector<std::string>{"case", "setup", "particles", "steps", "sim_s", "wall_s", "finite",
                                   "inside", "energy_ok", "completed", "bound", "max_kinetic_J",
                                   "bound_J", "final_kinetic_J", "settled_bound_J", "pass",
                                   "first_failure"});
      energy = std::make_unique<pbf_bench::CsvWriter>(
          out_dir + (reduced ? "/stress_energy_reduced.csv" : "/stress_energy.csv"),
          std::vector<std::string>{"case", "t", "kinetic_J", "bound_J"});
    }
    std::printf("pbf_stress: %zu cases%s\n", cases.size(), reduced ? " (reduced)" : "");
    std::printf("%-28s %6s %7s %7s %6s %6s %6s %10s %9s %9s %8s %6s\n", "case", "N", "steps", "sim[s]",
                "finite", "inside", "done", "bound", "maxE/bnd", "endE/set", "wall[s]", "result");
    int failures = 0, run = 0, skipped = 0;
    for (const auto& c : cases) {
      if (!only.empty() && c.name.find(only) == std::string::npos) continue;
      ++run;
      pbf_bench::Progress p(c.name, progress);
      const pbf_bench::StressResult r = pbf_bench::runStressCase(c, &p);
      p.done();
      if (r.skipped) {  // the overrides conflict with this case's own settings: say so, go on
        ++skipped;
        std::printf("%-28s SKIPPED\n    %s\n", r.name.c_str(), r.first_failure.c_str());
        if (csv)
          csv->row({r.name, c.setup, 0LL, 0LL, 0.0, 0.0, 0LL, 0LL, 0LL, 0LL, std::string("-"), 0.0, 0.0, 0.0,
                    0.0, 0LL, r.first_failure});
        continue;
      }
      failures += r.pass() ? 0 : 1;
      char settled[16] = "-";
      if (r.final_bound > 0) std::snprintf(settled, sizeof settled, "%.3f", r.final_kinetic / r.final_bound);
      std::printf("%-28s %6zu %7lld %7.2f %6s %6s %6s %10s %9.3f %9s %8.1f %6s\n", r.name.c_str(), r.particles,
                  r.steps, r.sim_seconds, mark(r.finite), mark(r.inside), mark(r.completed),
                  r.bound_name.c_str(), r.max_kinetic / r.bound, settled, r.wall_seconds,
                  r.pass() ? "PASS" : "FAIL");
      if (r.gain_bound > 0)
        std::printf("    fluid + bodies: mechanical energy rose at most %.3g J above its start (allowed %.3g J)\n",
                    r.max_gain, r.gain_bound);
      if (!r.pass()) std::printf("    first failure: %s\n", r.first_failure.c_str());
      std::fflush(stdout);
      if (csv)
        csv->row({r.name, c.setup, (long long)r.particles, r.steps, r.sim_seconds, r.wall_seconds,
                  (long long)r.finite, (long long)r.inside, (long long)r.energy_ok, (long long)r.completed,
                  r.bound_name, r.max_kinetic, r.bound, r.final_kinetic, r.final_bound, (long long)r.pass(),
                  r.first_failure});
      if (energy)
        for (std::size_t k = 0; k < r.trace_t.size(); ++k)
          energy->row({r.name, r.trace_t[k], r.trace_kinetic[k], r.bound});
    }
    std::printf("pbf_stress: %d of %d cases passed", run - failures - skipped, run);
    if (skipped) std::printf(", %d skipped (their settings conflict with --set)", skipped);
    std::printf("\n");
    return failures ? 1 : 0;
  } catch (const std::exception& e) {
    std::cerr << "\npbf_stress: " << e.what() << "\n";
    return 1;
  }
}
