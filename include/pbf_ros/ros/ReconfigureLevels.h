#pragma once
// Level bits of config/Fluid.cfg, one per subsystem. The reconfigure callback receives the
// OR of the bits of every changed parameter and redoes only what those subsystems need.

#include <cstdint>

namespace pbf_ros {
namespace level {

constexpr std::uint32_t kSolver = 1;        // iterations, tolerance, epsilon, s_corr, unilateral
constexpr std::uint32_t kVelocity = 2;      // XSPH, vorticity
constexpr std::uint32_t kTimeStep = 4;      // dt, CFL
constexpr std::uint32_t kNeighbors = 8;     // skin
constexpr std::uint32_t kForces = 16;       // gravity
constexpr std::uint32_t kFluid = 32;        // rest density, support radius, robustness caps
constexpr std::uint32_t kResolution = 64;   // particle spacing: rebuilds the fluid
constexpr std::uint32_t kScene = 128;       // scene: reloads and rebuilds the fluid
constexpr std::uint32_t kPublishing = 256;  // publish rates
constexpr std::uint32_t kPacing = 512;      // real-time factor
constexpr std::uint32_t kBoundary = 1024;   // walls and obstacles: wall density, friction
constexpr std::uint32_t kRender = 2048;     // surface rendering: camera, size, filter, rate

// Subsystems handled by SolverParams alone: the fluid keeps its state.
constexpr std::uint32_t kAnySolverParam =
    kSolver | kVelocity | kTimeStep | kNeighbors | kForces | kFluid | kResolution | kBoundary;
// Subsystems that rebuild the fluid from the scene.
constexpr std::uint32_t kAnyReset = kResolution | kScene;

}  // namespace level
}  // namespace pbf_ros
