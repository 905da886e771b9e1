#pragma once
// Fluid that enters and leaves a running solver between steps: the scene's emitters
// (Emitter.h) and drains (Drain.h), and blocks added on request (the node's ~emit). Keeps
// the books that prove volume conservation: after every change
//   solver.size() == initialParticles() + emitted() - drained()
// i.e. what entered minus what left is the change of the fluid's mass, to the particle.
//
// New particles sit on the solver's lattice (spacing d, so at rest density with the
// calibrated mass) and never where something already is: a site is skipped when it lies
// outside the container (closer than d/2 to a wall), inside a solid (closer than d/2), or
// closer than kSiteClearance * d to an existing particle.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "pbf_ros/core/Drain.h"
#include "pbf_ros/core/Emitter.h"
#include "pbf_ros/core/PbfSolver.h"
#include "pbf_ros/core/Scene.h"

namespace pbf {

// An existing particle closer than this many spacings to a site blocks it. Neighbours in
// a resting lattice are exactly d apart; the margin lets the layers of a jet, which the
// solver moves by what it computes rather than by exactly d per layer, follow each other
// without a layer being dropped for round-off.
constexpr float kSiteClearance = 0.9f;

// What became of the lattice sites of one addition.
struct SiteCount {
  std::size_t added = 0;
  std::size_t occupied = 0;  // an existing particle was there
  std::size_t in_solid = 0;  // inside an obstacle
  std::size_t outside = 0;   // outside the container
};

// Of `sites` (fluid_domain), keeps those where a new particle fits (see above) and counts
// the rest; `count.added` is the number kept.
SiteCount keepFreeSites(const PbfSolver& solver, std::vector<Eigen::Vector3f>& sites);

// The lattice sites (spacing d) filling a block, laid out as Scene::initialParticles lays
// out a scene's block. Empty when the block is invalid.
std::vector<Eigen::Vector3f> blockSites(const FluidBlock& block, float d);

// The speed [m/s] at which emitter `e` sends fluid at spacing d: its `speed`, or its `rate`
// over the area of its nozzle's lattice sites (which depends on d).
double emitterSpeed(const Emitter& e, float d);

// Empty when a block can be emitted; otherwise what is wrong, naming the field ("min",
// "max", "center", "radius", "velocity").
std::string validateBlock(const FluidBlock& block);

class FluidSources {
 public:
  FluidSources() = default;
  // Throws std::invalid_argument naming the first unusable emitter or drain.
  FluidSources(std::vector<Emitter> emitters, std::vector<Drain> drains,
               std::size_t initial_particles);

  const std::vector<Emitter>& emitters() const { return emitters_; }
  const std::vector<Drain>& drains() const { return drains_; }
  // Where emitter k's frame is now (fluid_domain); a non-finite pose throws, nothing changes.
  // An emitter attached to a frame stays shut until its frame's pose has been set once
  // (rather than emitting at the fluid frame's origin before tf knows the frame).
  void setEmitterPose(std::size_t k, const Eigen::Isometry3f& pose);

  struct StepResult {
    std::size_t emitted = 0;
    std::size_t drained = 0;
    // Emitters whose layer did not fit under max_particles this step (dropped, not queued).
    std::vector<std::size_t> held_by_limit;
    // Emitters with more layers due than a step adds (the oldest were dropped): a jet faster
    // than 8 spacings per step, with a fixed or first time step.
    std::vector<std::size_t> too_fast;
  };
  // After a solver step of `dt` (ending at solver.time()): drains remove what is inside
  // them, then every open emitter adds the layers that are due. Never grows the solver
  // beyond max_particles.
  StepResult afterStep(PbfSolver& solver, double dt, std::size_t max_particles);

  // Adds `block` (in the frame at `pose`, fluid_domain when identity) at rest, or with its
  // velocity. All or nothing: throws std::invalid_argument naming the field, saying that
  // no site is free, or naming the limit when it would bring the fluid beyond
  // max_particles; the solver is untouched then.
  SiteCount emitBlock(PbfSolver& solver, const FluidBlock& block, const Eigen::Isometry3f& pose,
                      std::size_t max_particles);

  std::size_t initialParticles() const { return initial_particles_; }
  std::uint64_t emitted() const { return emitted_; }  // by emitters and emitBlock
  std::uint64_t drained() const { return drained_; }
  std::uint64_t emittedBy(std::size_t emitter) const { return state_.at(emitter).emitted; }

 private:
  struct EmitterState {
    double travel = 0.0;          // how far the last layer has gone [m]
    std::uint64_t emitted = 0;
    bool placed = false;          // its pose is known (always, without a frame)
    // The nozzle's lattice sites in its plane, for the spacing they were made at: made once,
    // not at every step (a nozzle 200 spacings wide has 125 000).
    std::vector<Eigen::Vector2f> disc;
    float disc_spacing = 0.0f;
  };
  std::size_t emitLayers(PbfSolver& solver, std::size_t k, double dt, std::size_t max_particles,
                         StepResult& result);

  std::vector<Emitter> emitters_;
  std::vector<Drain> drains_;
  std::vector<EmitterState> state_;
  std::size_t initial_particles_ = 0;
  std::uint64_t emitted_ = 0;
  std::uint64_t drained_ = 0;
};

}  // namespace pbf
