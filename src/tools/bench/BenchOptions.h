#pragma once
// What every pbf_bench study needs to know: where to write, how thorough to be.

#include <string>

namespace pbf_bench {

struct BenchOptions {
  std::string out_dir = "bench_out";
  std::string scenes_dir;       // config/scenes
  std::string reference_csv;    // Martin & Moyce surge front
  bool quick = false;           // smaller, shorter runs for fast iteration (not for figures)
  bool progress = true;
  int threads = 0;              // 0: OpenMP default
  // YAML map of solver parameters (--set key=value) applied to the dam-break study's
  // scenes, e.g. to validate proposed defaults. The sweep and scaling set their own.
  std::string solver_overrides;
};

}  // namespace pbf_bench
