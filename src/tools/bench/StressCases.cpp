#include "bench/StressCases.h"

#include <chrono>
#include <cmath>
#include <cstdio>

#include "bench/BenchScenes.h"
#include "bench/EnergyBound.h"
#include "bench/Progress.h"
#include "bench/SceneRun.h"
#include "pbf_ros/core/Metrics.h"
#include "pbf_ros/core/RigidBody.h"
#include "pbf_ros/core/Scene.h"

namespace pbf_bench {

namespace {

// PBF only dissipates: the mechanical energy of fluid and bodies may rise above its start by
// round-off and the start lattice's settling, not by a share of what the bodies bring.
constexpr double kGainFraction = 0.02;

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

// The tank at d = 0.04 (water 0.3 m deep) with a ball of `density` (R 6 cm) whose centre is
// at `height`, and with `raft` a flat box (8 cm high) of the same density and centre height
// beside it.
pbf::Scene floatingScene(double density, float height, bool raft) {
  pbf::Scene s = tank();
  pbf::Obstacle ball;
  ball.shape = pbf::Obstacle::Shape::Sphere;
  ball.radius = 0.06f;
  ball.pose.translation() = Eigen::Vector3f(0.12f, 0.2f, height);
  s.obstacles.push_back(ball);
  if (raft) {
    pbf::Obstacle box;
    box.shape = pbf::Obstacle::Shape::Box;
    box.half_extents = Eigen::Vector3f(0.08f, 0.06f, 0.04f);
    box.pose.translation() = Eigen::Vector3f(0.28f, 0.2f, height);
    s.obstacles.push_back(box);
  }
  for (std::size_t k = 0; k < s.obstacles.size(); ++k) {
    const pbf::Obstacle& o = s.obstacles[k];
    const double volume = o.shape == pbf::Obstacle::Shape::Sphere ? 4.0 / 3.0 * M_PI * std::pow(o.radius, 3)
                                                                  : 8.0 * o.half_extents.prod();
    const double mass = density * volume;
    s.floating.push_back({k, mass, pbf::solidInertia(s.obstacles[k], mass)});
  }
  return s;
}
void iterations(pbf::SolverParams& p, int n) {
  p.min_iterations = p.max_iterations = n;
  p.density_tolerance = 0.0f;
}

// Kinetic plus potential energy of the fluid and the bodies (z up, the solver's gravity).
double mechanicalEnergy(const pbf::PbfSolver& s, const pbf::FloatingBodies& bodies) {
  const double m = s.params().particleMass(), g = -s.params().gravity.z();
  double e = 0.0;
  for (std::size_t i = 0; i < s.size(); ++i)
    e += 0.5 * m * s.velocities()[i].squaredNorm() + m * g * s.positions()[i].z();
  for (const auto& [index, body] : bodies.bodies())
    e += body.kineticEnergy() + body.mass() * g * body.shape().pose.translation().z();
  return e;
}

}  // namespace

std::vector<StressCase> stressCases(bool reduced) {
  std::vector<StressCase> c;
  const double seconds = reduced ? 0.4 : 2.0;  // dam break hits the far wall at ~0.6 s
  auto add = [&c](std::string name, std::string setup, Make make, long long steps, double secs,
                  bool overlapping = false) {
    c.push_back({std::move(name), std::move(setup), std::move(make), steps, secs, overlapping, {}});
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
  add("s_corr k=10", "dam break d=0.04, scorr_k = 10 (100x the paper's 0.1), Jacobi solve",
      sceneWith(damBreak, [](pbf::SolverParams& p) {
        p.gauss_seidel = false;  // s_corr acts on the Jacobi corrections only
        p.scorr_k = 10.0f;
      }), 0,
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

  // Floating bodies (two-way coupling, explicit): a heavy ball dropped from above the
  // water, and a raft and a buoy at a coarse fixed time step. The whole system's energy
  // never rises above its start (StressResult::max_gain).
  add("floating: stone dropped", "tank d=0.04, ball R 6 cm of 2000 kg/m^3 dropped from 0.45 m",
      [] { return makeSolver(floatingScene(2000.0, 0.45f, false)); }, 0, reduced ? 0.5 : 2.0);
  c.back().bodies = [] { return pbf::makeFloatingBodies(floatingScene(2000.0, 0.45f, false)); };
  // Raft and buoy start where they float (half submerged): nothing is dropped, so energy
  // the coupling made would show as a rise, not hide under what a fall dissipates.
  add("floating: raft and buoy, dt=1/60", "tank d=0.04, ball and box of 500 kg/m^3 at their water line, fixed dt 1/60 s",
      [] {
        pbf::Scene s = floatingScene(500.0, 0.3f, true);
        fixedDt(s.solver, 1.0f / 60);
        return makeSolver(s);
      },
      0, reduced ? 0.5 : 2.0);
  c.back().bodies = [] { return pbf::makeFloatingBodies(floatingScene(500.0, 0.3f, true)); };
  c.back().settle = 1.0;

  // Long run: sloshing tank (two water levels), default settings.
  const long long soak = reduced ? 3000 : 100000;
  add("sloshing soak " + std::to_string(soak) + " steps", "sloshing tank d=0.04 (500 particles), defaults",
      [] { return makeSolver(sloshingScene(0.04f)); }, soak, 0.0);
  return c;
}

void applySolverOverrides(std::vector<StressCase>& cases, const std::string& yaml) {
  pbf::SolverParams checked;
  pbf::applySolverYaml(yaml, "--set", checked);  // a bad key fails here, before any case runs
  for (auto& c : cases)
    c.make = [make = c.make, yaml]() {
      auto solver = make();
      pbf::SolverParams p = solver->params();
      // The keys and values passed on the defaults (above), so what fails here is their
      // combination with this case's own settings (the loader checks it, then the solver).
      try {
        pbf::applySolverYaml(yaml, "--set", p);
        solver->setParams(p);
      } catch (const std::exception& e) {
        throw OverrideConflict(std::string("skipped: the --set overrides conflict with this case's own settings: ") +
                               e.what());
      }
      return solver;
    };
}

StressResult runStressCase(const StressCase& c, Progress* progress) {
  StressResult r;
  r.name = c.name;
  const auto t0 = std::chrono::steady_clock::now();
  std::unique_ptr<pbf::PbfSolver> solver;
  try {
    solver = c.make();
  } catch (const OverrideConflict& e) {
    r.skipped = true;
    r.completed = false;
    r.first_failure = e.what();
    return r;
  }
  pbf::FloatingBodies bodies = c.bodies ? c.bodies() : pbf::FloatingBodies();
  while (solver->time() < c.settle - 1e-9)
    if (solver->step().failed) break;  // the run below reports it
  r.particles = solver->size();
  const EnergyBound eb = energyBound(solver->positions(), solver->velocities(), solver->params(), solver->container());
  r.bound = c.overlapping_start ? eb.speed_cap_bound : eb.physical();
  r.bound += bodiesAllowance(bodies, solver->params(), solver->container());
  const double e0 = bodies.empty() ? 0.0 : mechanicalEnergy(*solver, bodies);
  if (!bodies.empty()) r.gain_bound = kGainFraction * bodiesAllowance(bodies, solver->params(), solver->container());
  r.bound_name = c.overlapping_start ? "speed cap" : "physical";
  auto fail = [&](const std::string& what) {
    if (r.first_failure.empty()) {
      char buf[160];
      std::snprintf(buf, sizeof buf, "%s at step %lld (t = %.4f s)", what.c_str(), r.steps, solver->time());
      r.first_failure = buf;
    }
  };
  const long long trace_every = std::max(1LL, c.steps / 2000);
  const double t_end = c.settle + c.seconds;
  while (c.steps > 0 ? r.steps < c.steps : solver->time() < t_end - 1e-9) {
    bodies.prepare(*solver);
    const pbf::StepStats st = solver->step();
    if (st.failed) {
      r.completed = false;
      fail("step failed at the smallest dt");
      break;
    }
    bodies.afterStep(*solver, st.dt);
    ++r.steps;
    double kinetic = st.kinetic_energy;
    bool finite = pbf::allFinite(solver->positions()) && pbf::allFinite(solver->velocities());
    for (float rho : solver->densities()) finite = finite && std::isfinite(rho);
    for (const auto& [index, body] : bodies.bodies()) {
      kinetic += body.kineticEnergy();
      finite = finite && body.shape().pose.matrix().allFinite();
    }
    if (!finite || !std::isfinite(kinetic)) {
      r.finite = false;
      fail("non-finite state");
    }
    const long long outside = static_cast<long long>(pbf::countOutside(solver->positions(), solver->container(), 0.0f));
    if (outside > 0) {
      r.inside = false;
      r.outside_max = std::max(r.outside_max, outside);
      fail(std::to_string(outside) + " particles outside");
    }
    r.max_kinetic = std::max(r.max_kinetic, kinetic);
    r.final_kinetic = kinetic;
    if (r.steps % trace_every == 0) {
      r.trace_t.push_back(solver->time());
      r.trace_kinetic.push_back(kinetic);
    }
    if (!bodies.empty()) {
      r.max_gain = std::max(r.max_gain, mechanicalEnergy(*solver, bodies) - e0);
      if (!(r.max_gain <= r.gain_bound)) {
        r.energy_ok = false;
        fail("mechanical energy of fluid and bodies above its start");
      }
    }
    if (!(kinetic <= r.bound)) {
      r.energy_ok = false;
      fail("kinetic energy above the bound");
    }
    if (progress) {
      const double f = c.steps > 0 ? double(r.steps) / c.steps : (solver->time() - c.settle) / c.seconds;
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
  r.sim_seconds = solver->time() - c.settle;
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace pbf_bench
