#pragma once
// A scene: the container, the fluid it starts with, and the solver settings it wants.
// Scenes are YAML files (config/scenes/*.yaml); see config/scenes/dam_break.yaml for the
// documented format.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "pbf_ros/core/Drain.h"
#include "pbf_ros/core/Emitter.h"
#include "pbf_ros/core/Obstacle.h"
#include "pbf_ros/core/SolverParams.h"

namespace pbf {

// Thrown for a scene that cannot be used. what() names the file, the key and what was
// expected, e.g. "dam_break.yaml: key 'fluid[0].max': expected a list of 3 numbers".
class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct FluidBlock {
  enum class Shape { Box, Sphere };
  Shape shape = Shape::Box;
  Eigen::Vector3f min = Eigen::Vector3f::Zero();   // Box
  Eigen::Vector3f max = Eigen::Vector3f::Zero();   // Box
  Eigen::Vector3f center = Eigen::Vector3f::Zero();  // Sphere
  float radius = 0.0f;                             // Sphere
  Eigen::Vector3f velocity = Eigen::Vector3f::Zero();  // initial velocity [m/s]
  // tf frame the block is given in ("" = the scene's container_frame, if any): the node
  // seeds the block where that frame is now, so a reset refills a tilted cup or a moved
  // tank, not the place where it stood at rest.
  std::string frame;
};

// The cubic lattice of spacing d in a block's bounding box, centred in it: n sites per axis
// from `start` (cell-centred). `slack` (in spacings) lets a size a hair short of a whole
// number of spacings (round-off: 0.33f - 0.21f = 3.9999 d) count as whole.
struct BlockLattice {
  Eigen::Vector3f start;
  Eigen::Vector3i n;
};
BlockLattice blockLattice(const FluidBlock& b, float d, float slack = 0.0f);

// Upper bounds on what a scene file may ask for: a hostile or broken file is refused with
// a clear message instead of taking minutes and gigabytes to load.
constexpr std::size_t kMaxSceneFileBytes = 1 << 20;  // 1 MiB (the shipped scenes: < 2 kB)
constexpr std::size_t kMaxFluidBlocks = 1000;
constexpr std::size_t kMaxObstacles = 256;
constexpr std::size_t kMaxSceneEmitters = 64;
constexpr std::size_t kMaxSceneDrains = 64;
// A nozzle wider than this many spacings would emit ~10^5 sites a layer: refused.
constexpr float kMaxEmitterRadiusInSpacings = 200.0f;

// An obstacle the fluid moves (RigidBody.h, FloatingBodies.h). Its obstacle's `frame` is the
// tf frame the node publishes the body's pose on (offset identity), `pose` where it starts.
struct FloatingBodySpec {
  std::size_t obstacle = 0;  // index into Scene::obstacles
  double mass = 0.0;         // [kg]
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();  // about its origin, body axes [kg m^2]
};

struct Scene {
  std::string name;
  std::string source;                   // file it came from ("" when built in code)
  Eigen::AlignedBox3f container;        // in the fluid_domain frame [m]
  std::vector<FluidBlock> fluid;
  std::vector<Obstacle> obstacles;      // poses in fluid_domain (or offsets in their frame)
  std::vector<FloatingBodySpec> floating;  // obstacles marked `dynamic`
  std::vector<Emitter> emitters;        // nozzles that add fluid while it runs (FluidSources.h)
  std::vector<Drain> drains;            // regions that remove the fluid entering them
  // tf frame the container is attached to ("" = fixed in fluid_domain): the node moves
  // the container with it (sloshing, carrying).
  std::string container_frame;
  SolverParams solver;                  // defaults overridden by the file's 'solver:' map
  // Pose of fluid_domain in world (the static tf world -> fluid_domain).
  Eigen::Vector3f domain_translation = Eigen::Vector3f::Zero();
  Eigen::Vector3f domain_rpy = Eigen::Vector3f::Zero();  // roll, pitch, yaw [rad]

  // Particles on a cubic lattice of spacing solver.particle_spacing filling every block,
  // cell-centred (first layer at d/2 from a block's face). Overlaps are filled once;
  // points inside an obstacle (closer than d/2 to it) are left out.
  // `block_of`, when given, receives the index of the block each particle came from.
  void initialParticles(std::vector<Eigen::Vector3f>& positions,
                        std::vector<Eigen::Vector3f>& velocities,
                        std::vector<std::uint32_t>* block_of = nullptr) const;

  // Checks, without allocating, that initialParticles() gives between 1 and max_particles
  // particles: "" when it does, otherwise why not (how many it would need, or that the
  // obstacles leave none). Costs O(blocks) for a lattice that clearly fits or clearly does
  // not, and never walks more than a few times max_particles lattice points.
  // `limit_name` is what the message calls the limit (the node's ~max_particles, a tool's
  // option).
  std::string checkParticleCount(std::size_t max_particles,
                                 const std::string& limit_name = "~max_particles") const;

  // Whether obstacle `index` floats (the node moves it, not tf).
  bool floats(std::size_t index) const;

  // The frame block `index` is given in (its own, else container_frame; "" = fluid_domain).
  const std::string& blockFrame(std::size_t index) const;

  // Empty when usable; otherwise what is wrong (container, blocks outside it, solver).
  std::string validate() const;
};

// Parses a scene file. Throws SceneError (file, key, expectation) for anything wrong,
// including a path that is not a regular file or is larger than kMaxSceneFileBytes.
Scene loadSceneFile(const std::string& path);

// Parses YAML text; 'origin' names it in error messages.
Scene loadSceneString(const std::string& yaml_text, const std::string& origin);

// Applies the keys of a YAML 'solver:' map onto params (shared with parameter files).
// Unknown keys and wrong types throw SceneError naming origin and key.
void applySolverYaml(const std::string& yaml_text, const std::string& origin,
                     SolverParams& params);

// "dam_break" -> "<scenes_dir>/dam_break.yaml"; a path with '/' or ending in .yaml is
// used as is. Throws SceneError when the file does not exist (listing the known scenes) or
// is not a regular file (a directory, a device).
std::string resolveScenePath(const std::string& name_or_path, const std::string& scenes_dir);

}  // namespace pbf
