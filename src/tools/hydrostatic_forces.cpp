// pbf_hydrostatic_forces: the fluid's force on a solid held in a resting tank against
// Archimedes, at a chosen resolution (the README's "Forces on solids" figures; the unit
// test test_core_solid_wrenches checks the shipped cases). No ROS.
//
//   pbf_hydrostatic_forces SHAPE SPACING [TANK DEPTH SIZE HEIGHT [WARM SPAN [HALF_HEIGHT]]]
//     SHAPE    sphere (SIZE = radius) or box (SIZE = half width; HALF_HEIGHT, default 0.6 SIZE)
//     SPACING  particle spacing [m]; every other solver setting is the shipped default
//     TANK     square tank width [m] (0.2), DEPTH fluid depth [m] (0.15)
//     SIZE     [m] (0.045), HEIGHT of the solid's centre [m] (0.07)
//     WARM     settling time before measuring [s] (1.0), SPAN averaging time [s] (0.5)
// Prints the time-averaged force on the solid, rho0 g V, the container's share, the fluid's
// weight and the settled free-surface height.

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "ToolArguments.h"
#include "pbf_ros/core/Metrics.h"
#include "pbf_ros/core/PbfSolver.h"
#include "pbf_ros/core/SceneSetup.h"

namespace {
const char* const kArgNames[] = {"", "SHAPE", "SPACING", "TANK", "DEPTH", "SIZE", "HEIGHT",
                                 "WARM", "SPAN", "HALF_HEIGHT"};

// Argument i, a finite number > 0 (every one is a length or a time), or `fallback` when not
// given; anything else ends the program naming it ("nan", "-0.04", "abc").
double arg(int argc, char** argv, int i, double fallback) {
  if (argc <= i) return fallback;
  try {
    return pbf_tools::finitePositive(kArgNames[i], argv[i]);
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "pbf_hydrostatic_forces: %s\n", e.what());
    std::exit(2);
  }
}
}  // namespace

int main(int argc, char** argv) {
  if (argc < 3 || (std::string(argv[1]) != "sphere" && std::string(argv[1]) != "box")) {
    std::fprintf(stderr, "usage: pbf_hydrostatic_forces sphere|box SPACING [TANK DEPTH SIZE HEIGHT [WARM SPAN [HALF_HEIGHT]]]\n");
    return 2;
  }
  const bool sphere = std::string(argv[1]) == "sphere";
  const float spacing = static_cast<float>(arg(argc, argv, 2, 0.01));
  const float tank = static_cast<float>(arg(argc, argv, 3, 0.2)), depth = static_cast<float>(arg(argc, argv, 4, 0.15));
  const float size = static_cast<float>(arg(argc, argv, 5, 0.045)), height = static_cast<float>(arg(argc, argv, 6, 0.07));
  const double warm = arg(argc, argv, 7, 1.0), span = arg(argc, argv, 8, 0.5);
  const float half_height = static_cast<float>(arg(argc, argv, 9, 0.6 * size));

  pbf::Scene scene;
  scene.name = "hydrostatic_forces";
  scene.container = Eigen::AlignedBox3f(Eigen::Vector3f::Zero(), Eigen::Vector3f(tank, tank, depth + 0.1f));
  pbf::FluidBlock block;
  block.max = Eigen::Vector3f(tank, tank, depth);
  scene.fluid.push_back(block);
  scene.solver.particle_spacing = spacing;
  pbf::Obstacle solid;
  double volume;
  if (sphere) {
    solid.shape = pbf::Obstacle::Shape::Sphere;
    solid.radius = size;
    volume = 4.0 / 3.0 * M_PI * std::pow(size, 3);
  } else {
    solid.shape = pbf::Obstacle::Shape::Box;
    solid.half_extents = Eigen::Vector3f(size, size, half_height);
    volume = 8.0 * size * size * half_height;
  }
  solid.pose.translation() = Eigen::Vector3f(0.5f * tank, 0.5f * tank, height);
  scene.obstacles.push_back(solid);
  const std::string problem = scene.validate();
  if (!problem.empty()) {
    std::fprintf(stderr, "pbf_hydrostatic_forces: %s\n", problem.c_str());
    return 2;
  }

  const std::string count = scene.checkParticleCount(1000000, "this tool's limit");
  if (!count.empty()) {
    std::fprintf(stderr, "pbf_hydrostatic_forces: %s\n", count.c_str());
    return 2;
  }

  pbf::PbfSolver solver;
  try {  // a solid the solver refuses (a radius of 0 once rounded) is named, not an abort
    pbf::setUpSolver(scene, solver);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pbf_hydrostatic_forces: %s\n", e.what());
    return 2;
  }
  solver.advance(warm);
  solver.setWrenchTracking(true);
  double t = 0.0;
  int failed_in_a_row = 0;
  Eigen::Vector3d on_solid = Eigen::Vector3d::Zero(), on_container = Eigen::Vector3d::Zero();
  while (t < span) {
    const pbf::StepStats stats = solver.step();
    if (stats.failed) {
      if (++failed_in_a_row == 10) {
        std::fprintf(stderr, "pbf_hydrostatic_forces: 10 steps in a row failed; no figure\n");
        return 1;
      }
      continue;
    }
    failed_in_a_row = 0;
    on_solid += stats.dt * solver.wrenches().obstacles[0].force;
    on_container += stats.dt * solver.wrenches().container.force;
    t += stats.dt;
  }
  on_solid /= t;
  on_container /= t;
  const double buoyancy = solver.params().rest_density * 9.81 * volume;
  const double weight = solver.size() * double(solver.params().particleMass()) * 9.81;
  std::printf("%s %.4g m at spacing %.4g m (%zu particles, %.1f particles across): "
              "F = (%.3f, %.3f, %.3f) N, rho0 g V = %.3f N (%+.2f %%); container %.3f N, "
              "container + solid %.3f N vs weight %.3f N (%+.3f %%); level %.4f m\n",
              argv[1], size, spacing, solver.size(), 2.0 * size / spacing, on_solid.x(), on_solid.y(),
              on_solid.z(), buoyancy, 100.0 * (on_solid.z() / buoyancy - 1.0), on_container.z(),
              -(on_container.z() + on_solid.z()), weight,
              100.0 * (-(on_container.z() + on_solid.z()) / weight - 1.0),
              pbf::freeSurfaceHeight(solver.positions(), spacing, scene.container));
  return 0;
}
