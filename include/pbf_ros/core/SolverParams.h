#pragma once
// Every tunable of the PBF solver, in SI units. Plain data: the ROS layer fills it from
// parameters / dynamic_reconfigure, tools and tests fill it directly.

#include <Eigen/Core>
#include <string>

namespace pbf {

// Vorticity confinement adds energy: it spins up any vortex at a rate of about epsilon,
// against the damping of XSPH and the solve at the scale h, which grows as h shrinks. With
// the shipped XSPH a tank at rest stays at rest up to 5 1/s at every spacing tried
// (hydrostatic_tank for 2-3 s: rms speed 0.054 m/s at d = 0.04 m against 0.029 without
// confinement, 0.028 against 0.020 at 0.02 m); at 10 1/s it stirs the water at d = 0.04 m
// (0.21 m/s) and at 30-100 1/s at every spacing, up to the speed cap. So the parameter
// cannot mean the same at every spacing; its range ends where it is calm at all of them.
constexpr float kMaxVorticityEpsilon = 5.0f;

struct SolverParams {
  // --- fluid ---------------------------------------------------------------------------
  float rest_density = 1000.0f;        // rho0 [kg/m^3]
  float particle_spacing = 0.02f;      // d [m]: initial lattice spacing, "particle diameter"
  float support_radius_factor = 2.0f;  // h = factor * d (2 -> about 33 neighbours)
  Eigen::Vector3f gravity{0.0f, 0.0f, -9.81f};  // [m/s^2], z up (REP 103)

  // --- time stepping -------------------------------------------------------------------
  float time_step = 1.0f / 120.0f;     // dt when adaptive stepping is off [s]
  bool adaptive_time_step = true;      // CFL-limited dt in [min_time_step, max_time_step]
  float cfl_factor = 0.4f;             // max displacement per step as a fraction of d
  float min_time_step = 1.0e-5f;       // [s]
  // 1/240 s: the error at rest scales with g dt^2; with the tolerance below this keeps a
  // settled tank under 0.3 % compression (Pareto study, doc/validation.md).
  float max_time_step = 1.0f / 240.0f; // [s]

  // --- constraint solve ----------------------------------------------------------------
  // Shipped defaults from the Pareto study (doc/validation.md): iterate until the average
  // density error is below 0.3 % (about 3 Gauss-Seidel sweeps at rest, 1-2 in a dam break).
  // min_iterations 0 (the default) is the solve's own floor: one Gauss-Seidel sweep, or two
  // Jacobi corrections, because one Jacobi correction overshoots where corrections overlap
  // (walls, impacts) and the overshoot becomes speed that no density error shows (at half
  // the default dt a fine dam break reached the speed cap with one correction per step); a
  // sweep projects each constraint from the positions its neighbours left and does not.
  // max_iterations only bounds a step's cost; the tolerance is the accuracy asked for. A
  // Jacobi solve needs about (depth/d)^2 corrections to carry a column's pressure, so any
  // fixed cap binds in a deep or finely resolved fluid: 30 did in the 0.3 m tank at
  // d = 0.0083 m (41 needed on average); with 100 at most one step in 360 stops there at
  // every spacing the validation runs. A step that stops at the cap says so
  // (StepStats::iteration_cap_reached, the node's /diagnostics).
  int min_iterations = 0;
  int max_iterations = 100;
  // Stop iterating once the average density error is below this (after min_iterations).
  // 0 means a fixed count: always max_iterations.
  float density_tolerance = 0.003f;
  // Constraint force mixing (eq 6's epsilon), relative to the constraint's own scale:
  // epsilon = cfm_relaxation * sum_j |grad_j C|^2 of a resting interior particle (which
  // grows like 1/d^2), so a resting particle's lambda is softened by the same fraction,
  // 1 / (1 + cfm_relaxation), at every spacing. Regularises lambda where the gradient sum
  // vanishes (isolated particles). 0.1 is what the validated absolute epsilon = 100 m^-2
  // amounted to at the default spacing of 0.02 m (it softened 30 % at 0.04 m, 4 % at 0.0126 m).
  float cfm_relaxation = 0.1f;
  // Warm start: each step's solve begins by applying half the previous step's summed
  // multiplier of every particle (as IISPH starts from half the previous pressure; rescaled
  // by (dt/dt_prev)^2, since the pressure it stands for is lambda / dt^2); that first
  // correction counts as an iteration. The solve then keeps each particle's summed
  // multiplier projected (a push can be taken back, at IISPH's relaxation of one half), and
  // density_tolerance bounds what is left to correct: compression and over-push. Off by
  // default: at the shipped tolerance it halves the density error at the same cost instead
  // of saving iterations; it pays at tight tolerances (doc/calibration.md, warm start).
  bool warm_start = false;
  // Chebyshev acceleration of the constraint iterations (ChebyshevAcceleration.h): rho is
  // the assumed spectral radius of the plain Jacobi iteration, in [0, 0.99]; 0: off. Too
  // low only accelerates less; too high would diverge, so the solve restarts the
  // acceleration whenever its error grows. 0.9 is the recommended value (doc/calibration.md,
  // acceleration). Like the warm start, it makes the solve projected. Not
  // applied while the solver measures the solids' wrenches (floating bodies, force topics).
  float chebyshev_rho = 0.0f;
  // Gauss-Seidel: the density constraints are projected one after another, each from the
  // positions the ones before it left (as PBD projects its constraints; GaussSeidelSweep.cpp),
  // instead of all at once from the same positions (Jacobi). A pressure then crosses the
  // fluid in fewer iterations: 2-2.7x fewer for the same tolerance (doc/performance.md).
  // The order is fixed by the grid (8 colours of blocks of cells, BlockColours.h), so results are the
  // same for any thread count. An iteration is one sweep, after which a density pass checks
  // the tolerance (the step then reuses that density). The default since session 21
  // (doc/performance.md). It replaces the Jacobi solve, so it does not combine with
  // warm_start, chebyshev_rho or scorr_k (setParams says so; set gauss_seidel false to use
  // them).
  bool gauss_seidel = true;
  // Over-relaxation of each Gauss-Seidel projection (SOR), in (0, 2): 1 is plain
  // Gauss-Seidel; above 1 each constraint over-corrects by this factor, which carries the
  // pressure faster. Dimensionless: the same at every spacing and time step. It is the
  // value at h = 2d; wider supports scale it by overlapRelaxation().
  float gauss_seidel_omega = 1.3f;
  // C = max(rho/rho0 - 1, 0): only compression is corrected, so surface particles with
  // missing neighbours are not pulled together (no clumping). Off: the seed's C = rho/rho0 - 1.
  bool unilateral_constraint = true;
  // Lend each particle by a free surface the density the air side would add were it fluid
  // (FreeSurfaceLend.h): the top layer then keeps a constraint of its own instead of sinking
  // into the layer below, and a resting tank keeps its level (doc/calibration.md). A
  // particle is lent what its neighbourhood lacked when it entered the fluid and loses it as
  // it is buried; a surface formed later is not lent. Off: the truncated sums of the seed.
  bool free_surface_lend = true;
  // Artificial pressure s_corr of eq 11 (Monaghan 2000), scaled by h^2 so that k is
  // dimensionless (see PbfSolver.cpp). k = 0 disables it at no cost.
  float scorr_k = 0.0f;
  float scorr_n = 4.0f;
  float scorr_delta_q = 0.2f;          // |dq| as a fraction of h

  // --- boundary -------------------------------------------------------------------------
  // Container walls lend density to particles within h (virtual fluid at rest density
  // beyond each wall, Boundaries.h). Off: the seed's clamp alone, under which the fluid
  // compacts against the walls.
  bool wall_density = true;
  // Friction of walls and obstacles, as a dimensionless wall-friction coefficient c_f of the
  // quadratic (bed) friction law tau = rho0 c_f |u_t| u_t (u_t: sliding velocity relative to
  // the surface). It acts on the particles within one spacing of a surface (the layer that
  // carries the wall's shear), integrated implicitly: the same physical law at every dt and
  // spacing. 0 = free slip (the default: no physical argument here fixes a value; smooth
  // channel beds have c_f ~ 0.002-0.005).
  float wall_friction = 0.0f;

  // --- velocity post-processing --------------------------------------------------------
  // XSPH (eq 10) as a kinematic viscosity nu [m^2/s]: the seed's per-step coefficient is
  // c = 22 nu dt / h^2 (the XSPH sum approximates h^2/22 times the Laplacian for Poly6), so
  // the fluid's viscosity does not change with dt or spacing. Where c would exceed 0.5 (a
  // coarse dt at a fine spacing) it is capped there, for stability: the only regime where
  // the parameter cannot mean the same. 1.7e-4 m^2/s is the seed's c = 0.01 at the default
  // dt = 1/240 s and h = 0.04 m. 0 disables it at no cost.
  float xsph_viscosity = 1.7e-4f;
  // Vorticity confinement f = epsilon h (N x omega) (Fedkiw et al. 2001: scaled by the
  // resolution, so it only restores vorticity lost at the scale of h) [1/s]; 0 = off, at
  // most kMaxVorticityEpsilon.
  float vorticity_epsilon = 0.0f;

  // --- neighbour search ----------------------------------------------------------------
  // Lists are built with radius h * (1 + skin) and reused while every particle moved less
  // than half the skin margin since the build. 0 rebuilds every step.
  float neighbor_skin = 0.0f;

  // --- robustness ----------------------------------------------------------------------
  int max_nan_retries = 6;             // halvings of dt before a step is given up
  // Hard cap on particle speed, as a multiple of the free-fall speed across the container
  // (sqrt(2 |g| L)). Only hostile settings reach it; it bounds kinetic energy. 0 = none.
  float max_speed_factor = 4.0f;

  // The iterations every step makes at least: min_iterations, or the solve's own floor.
  int minIterations() const { return min_iterations > 0 ? min_iterations : (gauss_seidel ? 1 : 2); }
  float supportRadius() const { return support_radius_factor * particle_spacing; }
  // The speed cap [m/s] in a container whose longest side is `longest_side` [m]:
  // max_speed_factor * sqrt(2 max(|g|, 9.81) L); 0 = none.
  float speedCap(float longest_side) const;
  // m = rho0 d^3: the water one cell of the start lattice holds. The fluid's weight, momentum
  // and kinetic energy, the forces on solids and the SPH volumes m / rho use it.
  float particleMass() const;
  // m / S, S = d^3 sum_lattice W (LatticeBoundary.h): what each particle adds to a density
  // sum, i.e. the density kernel normalised on the start lattice, so that a particle of the
  // cubic start lattice sits at exactly rho0 (with m itself it would sit at S rho0, 1.236 rho0
  // for h = 2d, and a fresh scene would burst at t = 0). The constraint is the issue's
  // "mass calibrated to the lattice" (C and its gradient only see m / S), while the fluid
  // keeps the mass of the volume it fills.
  float densityMass() const;
  // How much wider supports relax the solve: min(1, A(2) / A(f)), A =
  // latticeJacobiAmplification (LatticeBoundary.h), f the support factor; 1 at the shipped
  // h = 2d, where everything was validated, and below it; 0.42 at 3d. Above 2d more
  // neighbours' corrections overlap. The Jacobi solve's multipliers are scaled by it, so
  // that its worst mode overshoots as much as at 2d: unrelaxed it diverged (at 3d a resting
  // tank blew up, level halved, rms speed 1 m/s). The sweeps' gauss_seidel_omega is scaled
  // by it too: a projection then moves a neighbour, which ~3.4x as many projections move at
  // 3d, by as much of its overlap as at 2d; unscaled, the sweeps kept a resting tank at an
  // rms speed of 0.10 m/s at 3d and 0.18 m/s at 4d (0.02 at 2d), scaled 0.034 / 0.047.
  float overlapRelaxation() const;
  // epsilon of eq 6 [1/m^2] (cfm_relaxation times the resting constraint scale).
  float cfmEpsilon() const;
  // XSPH's per-step coefficient c for a step of dt.
  float xsphCoefficient(float dt) const;

  // The solve keeps each particle's summed multiplier <= 0 and may take pushes back
  // (ConstraintPasses.cpp): needed when pushes can overshoot (warm start, acceleration).
  bool projectedSolve() const {
    return unilateral_constraint && (warm_start || chebyshev_rho > 0.0f);
  }

  // Empty when every value is usable; otherwise a message naming the first bad field.
  std::string validate() const;
};

}  // namespace pbf
