#pragma once
// One hydrostatic-tank run: water at rest should stay at rest density, at the level its
// volume implies, and still. Errors are measured over the last third of the run (after
// the lattice has settled under gravity).

#include "bench/SceneRun.h"
#include "pbf_ros/core/Scene.h"

namespace pbf_bench {

struct HydrostaticResult {
  std::size_t particles = 0;
  double avg_density_error = 0.0;  // mean over the window of the per-step average
  double max_density_error = 0.0;  // max over the window of the per-step maximum
  double height_loss = 0.0;        // (H_volume - H_surface) / H_volume at the end
  // The same for the level of a uniform column holding the water's potential energy, 2 z_mean
  // (z_mean: the particles' mean height above the floor): the bulk's compression, however the
  // surface's layers sit (a sunken or rough top layer moves z_mean by a fifteenth of what it
  // moves the surface at d = 0.02 m). Exactly 0 for the start lattice.
  double mean_height_loss = 0.0;
  double residual_speed_max = 0.0; // [m/s] at the end
  double residual_speed_rms = 0.0; // [m/s] at the end
  double startup_speed_max = 0.0;  // [m/s] largest particle speed over the first kStartupSeconds
  // [m/s] The same over the first kFirstStepsSeconds only: a column whose solve stops at the
  // average tolerance falls as a block until the floor's compression reaches that average.
  double first_steps_speed_max = 0.0;
  // At the end, particles per d^3 in the bulk: at least 2 spacings from the side walls and the
  // floor, more than h below the free surface, between lattice half-planes (exactly 1 for the
  // start lattice). Beside height_loss it says whether the bulk or the surface lost the level.
  double bulk_number_density = 0.0;
  // At the end, the mean density (/ rho0) of the particles deeper than h below the free
  // surface whose centres lie within one spacing of exactly one wall (floor or side: the
  // first layer on a face), of two (an edge), of three (a corner), and of none (inside, for
  // comparison: the shipped tolerance lets the whole column sit ~0.3 % compressed). The
  // container's top is never wetted here.
  double interior_density = 0.0, face_density = 0.0, edge_density = 0.0, corner_density = 0.0;
  // The same at one depth, the floor's, where the column is most compressed and where every
  // corner lies: the first layer on the floor away from the side walls, on the floor by one
  // side wall (the bottom edges), and the second layer above the floor, away from every
  // wall (inside, one spacing higher). Beside corner_density they tell the walls' share of
  // an excess from the depth's.
  double floor_density = 0.0, bottom_edge_density = 0.0, second_layer_inside_density = 0.0;
  // At the end, per wetted wall the mean distance from it of the particles within one
  // spacing, the largest over the walls [spacings]: ~0.5 while the first layer touches the
  // wall, infinite when no particle is left within a spacing of one.
  double wall_gap = 0.0;
  double mean_iterations = 0.0;
  RunTotals totals;
};

// Issue 9's start-up window: a fresh tank's lattice should stay below 0.05 m/s throughout.
constexpr double kStartupSeconds = 0.5;
constexpr double kFirstStepsSeconds = 0.05;

HydrostaticResult runHydrostatic(const pbf::Scene& scene, double settle_seconds, Progress* progress);

}  // namespace pbf_bench
