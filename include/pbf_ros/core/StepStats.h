#pragma once
// What one solver step did and what it cost: the solver's answer to "what happened?".

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace pbf {

struct StageTimes {
  double neighbors_ms = 0.0;             // grid, sort, neighbour lists
  double solve_ms = 0.0;                 // constraint iterations (lambda, delta p, boundary)
  double viscosity_vorticity_ms = 0.0;   // final density, XSPH, vorticity confinement
  double other_ms = 0.0;                 // prediction, velocity update, statistics, guards
  double total_ms = 0.0;
};

// The stages a step skipped because the scene does not need them, as flags: a step
// allocates nothing for them; names() gives the strings the stats message carries.
class SkippedStages {
 public:
  enum Stage : std::uint32_t {
    kVorticity = 1u << 0,
    kXsph = 1u << 1,
    kScorr = 1u << 2,
    kNeighborSearch = 1u << 3,            // lists reused within the skin
    kIterationsAfterTolerance = 1u << 4,  // the tolerance was met before max_iterations
    kWrench = 1u << 5,                    // no wrench measured (set by the node)
    kDensityPass = 1u << 6,               // the solve's last lambda pass measured the density
  };
  void add(Stage stage) { bits_ |= stage; }
  bool has(Stage stage) const { return (bits_ & stage) != 0; }
  // In the order above: "vorticity", "xsph", "scorr", "neighbor_search",
  // "iterations_after_tolerance", "wrench", "density_pass".
  std::vector<std::string> names() const {
    static const char* const kNames[] = {"vorticity",  "xsph", "scorr", "neighbor_search",
                                         "iterations_after_tolerance", "wrench", "density_pass"};
    std::vector<std::string> out;
    for (std::uint32_t k = 0; k < sizeof(kNames) / sizeof(kNames[0]); ++k)
      if (bits_ & (1u << k)) out.emplace_back(kNames[k]);
    return out;
  }

 private:
  std::uint32_t bits_ = 0;
};

struct StepStats {
  std::uint32_t particle_count = 0;
  double dt = 0.0;                       // time step actually taken [s]
  int iterations = 0;                    // constraint iterations used (a warm start is one)
  int density_checks = 0;                // density passes of the Gauss-Seidel stop test
  int density_checks_stopped_early = 0;  // ... that stopped once the part measured failed it
  double final_sweep_residual = 0.0;     // mean compression each constraint had when the last
                                         // measured sweep reached it (Gauss-Seidel)
  bool iteration_cap_reached = false;    // stopped at max_iterations above density_tolerance
  bool warm_started = false;             // the solve began from the previous step's pressure
  double avg_density_error = 0.0;        // mean of max(rho/rho0 - 1, 0) after the step
  double max_density_error = 0.0;        // max of rho/rho0 - 1 after the step
  double max_speed = 0.0;                // [m/s]
  double kinetic_energy = 0.0;           // [J]
  int nan_retries = 0;                   // rejected attempts (non-finite values) this step
  int dense_retries = 0;                 // ... of them: particles packed far denser than a
                                         // fluid (more neighbour pairs than PbfSolver allows)
  bool failed = false;                   // no attempt succeeded: state left unchanged
  double initial_density_error = 0.0;    // mean compression of the prediction, before the solve
  bool neighbor_lists_reused = false;
  int neighbor_rebuilds_in_step = 0;     // skin exceeded by the corrections: lists rebuilt
  std::size_t grid_cells = 0;            // cells of the neighbour grid (it covers the fluid)
  bool speed_limited = false;            // the max_speed_factor cap acted this step
  StageTimes times;
  SkippedStages skipped_stages;
};

}  // namespace pbf
