#pragma once
// The hostile-case matrix of pbf_stress, shared with the reduced gtest (test/tools/).
// Each case builds a solver in a bad situation and runs it; pass means: no NaN/Inf in any
// position, velocity or density; no particle outside the container; kinetic energy within
// the bounds of EnergyBound.h; every step completed.

#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "pbf_ros/core/FloatingBodies.h"
#include "pbf_ros/core/PbfSolver.h"

namespace pbf_bench {

class Progress;

struct StressCase {
  std::string name;
  std::string setup;  // one line: scene, particles, the hostile setting
  std::function<std::unique_ptr<pbf::PbfSolver>()> make;
  long long steps = 0;     // run exactly this many solver steps, or else
  double seconds = 0.0;    // this much simulated time
  // Particles start overlapping: the cap bound applies during the run and the settled
  // bound at its end, instead of the physical bound throughout (EnergyBound.h).
  bool overlapping_start = false;
  // Rigid bodies coupled to the fluid (the scene's `dynamic` obstacles of the solver `make`
  // builds), moved after every step; empty = none. The energy checked is then the whole
  // system's: the bodies' kinetic energy counts with the fluid's, and the potential energy
  // they can give up with the budget (EnergyBound.h, bodiesAllowance).
  std::function<pbf::FloatingBodies()> bodies;
  // Simulated time the fluid settles around the bodies, held still, before the run and its
  // checks start (the start lattice's settling would hide what the coupling does).
  double settle = 0.0;
};

struct StressResult {
  std::string name;
  std::size_t particles = 0;
  long long steps = 0;
  double sim_seconds = 0.0, wall_seconds = 0.0;
  bool finite = true, inside = true, energy_ok = true, completed = true;
  // Not run: the solver overrides conflict with the case's own settings (first_failure says
  // how, naming the keys). Neither a pass nor a failure of the solver.
  bool skipped = false;
  long long outside_max = 0;        // most particles outside at any step
  double max_kinetic = 0.0, bound = 0.0;        // [J]; bound applied at every step
  double final_kinetic = 0.0, final_bound = 0.0;  // [J]; overlapping starts only
  std::string bound_name;                         // "physical" or "speed cap"
  // With floating bodies: the largest rise of the whole system's mechanical energy (fluid
  // and bodies, kinetic plus potential) above its start, and what is allowed (EnergyBound.h).
  double max_gain = 0.0, gain_bound = 0.0;
  std::string first_failure;        // what failed first, at which step
  // Kinetic energy over time (decimated to at most ~2000 samples) for plots.
  std::vector<double> trace_t, trace_kinetic;
  bool pass() const { return !skipped && finite && inside && energy_ok && completed; }
};

// reduced: the same kinds of case, short enough for ctest (well under a minute).
std::vector<StressCase> stressCases(bool reduced);

StressResult runStressCase(const StressCase& c, Progress* progress);

// What a case's solver factory throws when the overrides conflict with the case's settings.
struct OverrideConflict : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// Every case's solver gets these solver settings (YAML, e.g. "warm_start: true\n") on top
// of its own after it is built: options that are off by default go through the matrix too.
// A bad key throws (pbf::SceneError), naming it. A case whose own settings the solver
// refuses to combine with the overrides (the s_corr case's Jacobi solve with
// gauss_seidel: true) is skipped when run, with the solver's message, and the rest run.
void applySolverOverrides(std::vector<StressCase>& cases, const std::string& yaml);

}  // namespace pbf_bench
