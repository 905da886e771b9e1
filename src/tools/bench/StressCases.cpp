#include "bench/StressCases.h"

#include <chrono>
#include <cmath>
#include <cstdio>

#include "bench/BenchScenes.h"
#include "bench/EnergyBound.h"
#include "bench/Progress.h"
#include "bench/SceneRun.h"
#include "pbf_ros/core/Metrics.h"

namespace pbf_bench {

namespace {

using Points = std::vector<Eigen::Vector3f>;
using Make = std::function<std::unique_ptr<pbf::PbfSolver>()>;
using Tweak = std::function<void(pbf::SolverParams&)>;

// Coarse scenes keep the matrix fast: the hostile settings, not the particle count, are
// what is being tested. Dam break at d = 0.04: 2 400 particles, a violent flow.
pbf::Scene damBreak() { return damBreakScene(defaultScenesDir(), 0.04f); }
pbf::Scene tank() { return hydrostaticScene(defaultScenesDir(), 0.04f); }

Make sceneWith(std::function<pbf::Scene()> scene, Tweak tweak) {
  return [scene, tweak] {
    pbf::Scene s = scene();
    tweak(s.solver);
    return makeSolver(s);
  };
}

// A solver on `scene` whose particles are replaced by what `place` makes of the lattice.
Make particlesFrom(std::function<pbf::Scene()> scene, std::function<Points(const Points&, const pbf::Scene&)> place) {
  return [scene, place] {
    const pbf::Scene s = scene();
    auto solver = makeSolver(s);
    solver->setParticles(place(solver->positions(), s));
    return solver;
  };
}

void fixedDt(pbf::SolverParams& p, float dt) {
  p.adaptive_time_step = false;
  p.time_step = dt;
}
void iterations(pbf::SolverParams& p, int n) {
  p.min_iterations = p.max_iterations = n;
  p.density_tolerance = 0.0f;
}

}  // namespace

std::vector<StressCase> stressCases(bool reduced) {
  std::vector<StressCase> c;
  const double seconds = reduced ? 0.4 : 2.0;  // dam break hits the far wall at ~0.6 s
  auto add = [&c](std::string name, std::string setup, Make make, long long steps, double secs,
                  bool overlapping = false) {
    c.push_back({std::move(name), std::move(setup), std::move(make), steps, secs, overlapping});
  };

  // Time step, CFL off, default iterations.
  const std::vector<int> rates = reduced ? std::vector<int>{1000, 15} : std::vector<int>{1000, 240, 60, 30, 15};
  for (int hz : rates)
    add("dt=1/" + std::to_string(hz), "dam break d=0.04, fixed dt 1/" + std::to_string(hz) + " s",
        sceneWith(damBreak, [hz](pbf::SolverParams& p) { fixedDt(p, 1.0f / hz); }),
        hz == 1000 && reduced ? 200 : 0, hz == 1000 && reduced ? 0.0 : seconds);
  add("dt=1/15, 1 iteration", "dam break d=0.04, fixed dt 1/15 s, 1 iteration",
      sceneWith(damBreak, [](pbf::SolverParams& p) { fixedDt(p, 1.0f / 15); iterations(p, 1); }), 0, seconds);

  // Iterations, CFL on.
  const std::vector<int> iters = reduced ? std::vector<int>{1, 50} : std::vector<int>{1, 2, 5, 10, 20, 50};
  for (int n : iters)
    add("iterations=" + std::to_string(n), "dam break d=0.04, " + std::to_string(n) + " fixed iterations",
        sceneWith(damBreak, [n](pbf::SolverParams& p) { iterations(p, n); }), 0, reduced && n == 50 ? 0.08 : seconds);

  // Forces and coefficients far beyond their useful range.
  add("gravity x100", "dam break d=0.04, g = -981 m/s^2, CFL on",
      sceneWith(damBreak, [](pbf::SolverParams& p) { p.gravity *= 100.0f; }), 0, reduced ? 0.02 : 0.3);
  add("gravity x100, dt=1/60", "dam break d=0.04, g = -981 m/s^2, fixed dt 1/60 s",
      sceneWith(damBreak, [](pbf::SolverParams& p) { p.gravity *= 100.0f; fixedDt(p, 1.0f / 60); }), 0,
      reduced ? 0.1 : 0.5);
  add("XSPH nu=0.01", "dam break d=0.04, xsph_viscosity = 0.01 m^2/s (60x the default; c capped at 0.5)",
      sceneWith(damBreak, [](pbf::SolverParams& p) { p.xsph_viscosity = 0.01f; }), 0, seconds);
  add("s_corr k=10", "dam break d=0.04, scorr_k = 10 (100x the paper's 0.1)",
      sceneWith(damBreak, [](pbf::SolverParams& p) { p.scorr_k = 10.0f; }), 0,
      reduced ? 0.03 : 0.25);  // short: once it fails, particles clump and steps go N^2

  // Hostile initial states.
  const int blob = reduced ? 400 : 1000;
  add("all particles at one point", std::to_string(blob) + " particles at the centre of the tank",
      particlesFrom(tank, [blob](const Points&, const pbf::Scene& s) { return Points(blob, s.container.center()); }),
      0, reduced ? 0.3 : 1.0, true);
  add("coincident pairs", "tank lattice d=0.04 with every particle doubled in place",
      particlesFrom(tank, [](const Points& x, const pbf::Scene&) {
        Points twice = x;
        twice.insert(twice.end(), x.begin(), x.end());
        return twice;
      }),
      0, reduced ? 0.3 : 1.0, true);
  add("outside the box", "tank lattice d=0.04, every 5th particle moved 0.5 m..1 km outside",
      particlesFrom(tank, [](const Points& x, const pbf::Scene&) {
        Points moved = x;
        const Eigen::Vector3f offsets[4] = {{0.5f, 0, 0}, {0, -2.0f, 0}, {3.0f, -2.0f, 5.0f}, {-1000.0f, 0, -1000.0f}};
        for (std::size_t i = 0; i < moved.size(); i += 5) moved[i] += offsets[(i / 5) % 4];
        return moved;
      }),
      0, reduced ? 0.3 : 1.0, true);

  // Long run: sloshing tank (two water levels), default settings.
  const long long soak = reduced ? 3000 : 100000;
  add("sloshing soak " + std::to_string(soak) + " steps", "sloshing tank d=0.04 (500 particles), defaults",
      [] { return makeSolver(sloshingScene(0.04f)); }, soak, 0.0);
  return c;
}

StressResult runStressCase(const StressCase& c, Progress* progress) {
  StressResult r;
  r.name = c.name;
  const auto t0 = std::chrono::steady_clock::now();
  auto solver = c.make();
  r.particles = solver->size();
  const EnergyBound eb = energyBound(solver->positions(), solver->velocities(), solver->params(), solver->container());
  r.bound = c.overlapping_start ? eb.speed_cap_bound : eb.physical();
  r.bound_name = c.overlapping_start ? "speed cap" : "physical";
  auto fail = [&](const std::string& what) {
    if (r.first_failure.empty()) {
      char buf[160];
      std::snprintf(buf, sizeof buf, "%s at step %lld (t = %.4f s)", what.c_str(), r.steps, solver->time());
      r.first_failure = buf;
    }
  };
  const long long trace_every = std::max(1LL, c.steps / 2000);
  while (c.steps > 0 ? r.steps < c.steps : solver->time() < c.seconds - 1e-9) {
    const pbf::StepStats st = solver->step();
    if (st.failed) {
      r.completed = false;
      fail("step failed at the smallest dt");
      break;
    }
    ++r.steps;
    bool finite = pbf::allFinite(solver->positions()) && pbf::allFinite(solver->velocities());
    for (float rho : solver->densities()) finite = finite && std::isfinite(rho);
    if (!finite || !std::isfinite(st.kinetic_energy)) {
      r.finite = false;
      fail("non-finite state");
    }
    const long long outside = static_cast<long long>(pbf::countOutside(solver->positions(), solver->container(), 0.0f));
    if (outside > 0) {
      r.inside = false;
      r.outside_max = std::max(r.outside_max, outside);
      fail(std::to_string(outside) + " particles outside");
    }
    r.max_kinetic = std::max(r.max_kinetic, st.kinetic_energy);
    r.final_kinetic = st.kinetic_energy;
    if (r.steps % trace_every == 0) {
      r.trace_t.push_back(solver->time());
      r.trace_kinetic.push_back(st.kinetic_energy);
    }
    if (!(st.kinetic_energy <= r.bound)) {
      r.energy_ok = false;
      fail("kinetic energy above the bound");
    }
    if (progress) {
      const double f = c.steps > 0 ? double(r.steps) / c.steps : solver->time() / c.seconds;
      char detail[48];
      std::snprintf(detail, sizeof detail, "step %lld, t=%.3f s", r.steps, solver->time());
      progress->update(f, detail);
    }
  }
  if (c.overlapping_start) {
    r.final_bound = eb.settled();
    if (!(r.final_kinetic <= r.final_bound)) {
      r.energy_ok = false;
      fail("kinetic energy at the end above the settled bound");
    }
  }
  r.sim_seconds = solver->time();
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace pbf_bench
