#pragma once
// The Position Based Fluids solver (Macklin & Mueller 2013, the seed report's algorithm),
// with the additions our users need: unilateral constraint, vorticity confinement,
// tolerance-driven iterations, CFL time step, neighbour-list reuse and NaN rejection.
//
// Particles are kept sorted by grid cell (Morton order); ids() maps each slot back to the
// index the particle had when it was set, so callers can follow individual particles.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <vector>

#include "pbf_ros/core/Obstacle.h"
#include "pbf_ros/core/SolidWrench.h"
#include "pbf_ros/core/SolverParams.h"
#include "pbf_ros/core/StepStats.h"

namespace pbf {

class ContainerMirror;
struct NeighborArrays;
struct PairConstants;
struct Reflection;
class FreeSurfaceLend;
class LatticeBoundary;
class NeighborGrid;
class SolidBoundaries;
class ChebyshevAcceleration;
class BlockColours;
class PackedSlots;

class PbfSolver {
 public:
  PbfSolver();
  ~PbfSolver();
  PbfSolver(const PbfSolver&) = delete;
  PbfSolver& operator=(const PbfSolver&) = delete;

  // Throws std::invalid_argument (naming the field) for unusable parameters; the solver
  // keeps its previous parameters then. Changing spacing/rest density rescales mass only:
  // particles stay where they are.
  void setParams(const SolverParams& params);
  const SolverParams& params() const { return params_; }

  // Axis-aligned container in the fluid frame; particles are kept inside.
  void setContainer(const Eigen::AlignedBox3f& box);
  const Eigen::AlignedBox3f& container() const { return container_; }
  // Pose of the container box in the fluid frame (identity unless the node attaches the
  // container to a moving tf frame). Set between steps; the walls move to it during the
  // next step and push the fluid along.
  void setContainerPose(const Eigen::Isometry3f& pose);
  const Eigen::Isometry3f& containerPose() const { return container_pose_; }

  // Obstacles (validated; throws std::invalid_argument naming the bad one). Their poses
  // may be updated between steps with setObstaclePose().
  void setObstacles(const std::vector<Obstacle>& obstacles);
  void setObstaclePose(std::size_t index, const Eigen::Isometry3f& pose);
  const std::vector<Obstacle>& obstacles() const { return obstacles_; }

  // Replaces all particles. Velocities may be empty (zero). Non-finite input throws.
  void setParticles(const std::vector<Eigen::Vector3f>& positions,
                    const std::vector<Eigen::Vector3f>& velocities = {});

  // Between steps, the amount of fluid may change (ParticleChanges.cpp: sources, drains,
  // ~emit) without rebuilding anything else. Added particles get fresh ids (ids() of those
  // that remain never change; an id is never given twice until setParticles() starts anew)
  // and the solver's rest density and mass. Non-finite input or a size mismatch throws
  // std::invalid_argument and changes nothing. Returns the id of the first one added.
  std::uint32_t addParticles(const std::vector<Eigen::Vector3f>& positions,
                             const std::vector<Eigen::Vector3f>& velocities);
  // Removes the particles whose slot is flagged (remove.size() must equal size()); the
  // others keep their ids and their order. Returns how many were removed.
  std::size_t removeParticles(const std::vector<std::uint8_t>& remove);
  // The id the next added particle will get.
  std::uint32_t nextId() const { return next_id_; }

  // One step with the time step the parameters ask for (fixed or CFL). Never leaves
  // non-finite values in the state: a failed attempt is retried with half the dt.
  StepStats step();

  // One step of exactly dt (still halved on a non-finite result). dt must be > 0.
  StepStats stepWith(float dt);

  // Steps until exactly `duration` seconds are simulated (the last step is shortened).
  // Returns the stats of every step taken.
  std::vector<StepStats> advance(double duration);

  std::size_t size() const { return position_.size(); }
  const std::vector<Eigen::Vector3f>& positions() const { return position_; }
  const std::vector<Eigen::Vector3f>& velocities() const { return velocity_; }
  // After the last step, what the solids and the free surface lend included.
  const std::vector<float>& densities() const { return density_; }
  // What the free surface lends particle i in densities() [kg/m^3] (FreeSurfaceLend.h):
  // 0 with SolverParams::free_surface_lend off, or before the particle's first step.
  float surfaceLend(std::size_t i) const {
    return surface_lend_table_ && surface_lend_[i] > 0.0f ? surface_lend_[i] : 0.0f;
  }
  const std::vector<std::uint32_t>& ids() const { return id_; }
  // Neighbour count (within h) of each particle at the last density evaluation; small
  // counts mark surface particles (the renderer draws only those if it wants).
  const std::vector<std::uint16_t>& neighborCounts() const { return neighbor_count_; }
  double time() const { return time_; }
  std::uint64_t stepCount() const { return step_count_; }

  // The dt the next step() would take (fixed, or CFL from the current velocities).
  float nextTimeStep() const;

  // The fluid's force and torque on every solid (SolidWrench.h), measured while on. Off (the
  // default) it costs nothing; on, each step also records what every solid did to the fluid.
  void setWrenchTracking(bool on) { track_wrenches_ = on; }
  bool wrenchTracking() const { return track_wrenches_; }
  // Of the last step (valid == false when tracking was off or the step failed).
  const SolidWrenches& wrenches() const { return wrenches_; }
  // The most neighbour pairs a search may find: what the particles would have at 8 times
  // water's density, never below 2^22 (16 MiB) nor above NeighborGrid::kMaxPairs. A step
  // whose search finds more is rejected (StepStats::dense_retries).
  std::size_t neighborPairBound() const;
  // The speed no particle exceeds [m/s]: max_speed_factor times the free-fall speed across
  // the container (0 = no cap). Floating bodies keep to it too (FloatingBodies).
  float maxSpeedCap() const;

 private:
  bool attemptStep(float dt, StepStats& stats);
  bool predict(float dt);
  void updateNeighbors(StepStats& stats);
  void rebuildNeighborLists(const std::vector<Eigen::Vector3f>& points);
  bool listsStillValidFor(const std::vector<Eigen::Vector3f>& points) const;
  // True when it rebuilt them (and so reordered the particles).
  bool keepListsValidFor(const std::vector<Eigen::Vector3f>& points, StepStats& stats);
  // Measures the density (and counts the neighbours within h) at the predicted positions and
  // sets each particle's multiplier for the next delta-p pass: eq 11's (the warm start
  // pass: the kept one instead).
  enum class LambdaPass { kNewton, kWarmStart };
  void computeLambdas(float& avg_error, LambdaPass pass = LambdaPass::kNewton);
  // Scales (or clears) the multipliers kept from the last step for a step of dt; true when
  // the solve is to start from them.
  bool prepareWarmStart(float dt);
  struct Scorr;
  // Delta p from the multipliers of the pass, applied to the predictions and projected onto
  // the solids; a Newton pass adds the multipliers to lambda_sum_.
  void correctPositions(LambdaPass pass = LambdaPass::kNewton);
  void computeScorrScales(const Scorr& scorr);
  Eigen::Vector3f pairGradient(std::size_t i, std::uint32_t j) const;  // grad_i W, exact path
  // The Jacobi solve (JacobiSolve.cpp): false when a pass went non-finite or the lists
  // overflowed; sets the stats' iteration fields.
  bool solveJacobi(float dt, StepStats& stats, bool& ended_on_lambda_pass);
  // The Gauss-Seidel solve (GaussSeidelSweep.cpp, SolverParams::gauss_seidel): sweeps until
  // the tolerance; false when a sweep went non-finite. Sets the stats' iteration fields;
  // ended_on_density: the last density measured (density_) is at the final positions.
  bool solveGaussSeidel(StepStats& stats, bool& ended_on_density);
  // One sweep; returns the average compression each constraint had when it was projected.
  float gaussSeidelSweep();
  struct SweepContext;
  // rows: the calling thread's two gradient rows (SweepContext::rows).
  void projectDensityConstraint(std::size_t i, const SweepContext& sweep, float* rows);
  // The length of a sweep's gradient row for the current lists (the longest, rounded up).
  std::size_t gradientRowLength() const;
  void recordGaussSeidelBoundaryPush(std::size_t i, float lambda, const SweepContext& sweep);
  // Every prediction onto the solids (recording what they did while wrenches are tracked).
  void projectOntoSolids();
  // True when some particle settled elsewhere than its corrected prediction (a solid or
  // friction moved it).
  bool updateVelocities(float dt);
  SolidBoundaries boundaries() const;
  // The container's walls as mirror images (ContainerMirror.h); none without wall density.
  ContainerMirror containerMirror() const;
  Eigen::Vector3f imagePush(const NeighborArrays& arrays, const PairConstants& pc, std::size_t i,
                            const Reflection* refl, int reflections, bool neighbour_images_done) const;
  // Where the particles can be during the attempt in progress (FluidReach.cpp): obstacles
  // whose reach misses it are left out of every per-particle boundary test.
  void updateFluidReach();
  // The free surface's lend of particles that have none yet, measured at the positions the
  // step starts from (NewParticleLends.cpp); rebuilds the lists there when there are any.
  void measureNewLends();
  // Wrench tracking (WrenchTracking.cpp): what the solids did to the particles, by solid.
  void recordBoundaryDensityPush(const SolidBoundaries& solids);
  void applyDeltasRecordingBoundary(const SolidBoundaries& solids);
  // density_known: the solve's last lambda pass measured density_ and neighbor_count_ at
  // these very positions, in this order, so only the vorticity is left to compute.
  // Returns the packed positions (PackedSlots.h) it read, or nullptr: the velocity passes
  // that follow read them too, as nothing moves in between.
  const float* computeDensityAndVorticity(bool density_known);
  // Density measurements (DensityMeasurement.cpp). density_ and neighbor_count_ at `at`
  // (positions in the current lists' order; `packed`: the same in slots,
  // PackedSlots::packPositions, or nullptr).
  void measureDensity(const std::vector<Eigen::Vector3f>& at, const float* packed);
  struct DensityContext;
  DensityContext densityContext(const std::vector<Eigen::Vector3f>& at, const float* packed) const;
  void measureDensityOf(std::size_t i, const DensityContext& c);
  // The Gauss-Seidel stop test: whether the average compression max(rho/rho0 - 1, 0) at the
  // predictions is within `tolerance`, measuring density_ and neighbor_count_ there. It stops
  // measuring, if may_stop_early, once the part measured already exceeds the tolerance (the
  // rest of density_ is then stale: another sweep follows). `error`: the average, or on such
  // a stop (stopped_early) a lower bound.
  bool densityWithinTolerance(const float* packed, double tolerance, bool may_stop_early, double& error,
                              bool& stopped_early);
  void applyViscosityAndVorticity(float dt, const float* packed_positions);
  void enforceSpeedLimit(float dt, StepStats& stats);
  bool stateIsFinite() const;
  void gatherStats(StepStats& stats) const;
  void reorder(const std::vector<std::uint32_t>& order);

  SolverParams params_;
  // params_.overlapRelaxation(), taken once per setParams instead of once per iteration (it
  // looks the lattice's Fourier analysis up under a lock). 1 for the default support.
  float overlap_relaxation_ = 1.0f;
  Eigen::AlignedBox3f container_{Eigen::Vector3f(-1, -1, -1), Eigen::Vector3f(1, 1, 1)};
  Eigen::Isometry3f container_pose_ = Eigen::Isometry3f::Identity();
  Eigen::Isometry3f prev_container_pose_ = Eigen::Isometry3f::Identity();  // at step start
  std::vector<Obstacle> obstacles_;
  std::vector<Eigen::Isometry3f> prev_obstacle_pose_;

  // Particle state, all in grid (Morton) order.
  std::vector<Eigen::Vector3f> position_;    // x, at the start/end of a step
  std::vector<Eigen::Vector3f> velocity_;
  std::vector<std::uint32_t> id_;
  std::uint32_t next_id_ = 0;                // fresh ids for added particles
  // Per-step scratch, Jacobi style: each pass reads one array and writes another.
  std::vector<Eigen::Vector3f> predicted_;   // x*
  std::vector<Eigen::Vector3f> delta_;       // delta p, kept apart while wrenches are tracked
  std::vector<Eigen::Vector3f> corrected_;   // the corrected predictions, swapped in
  std::vector<Eigen::Vector3f> new_velocity_;
  std::vector<Eigen::Vector3f> vorticity_;
  std::vector<float> vorticity_norm_;        // |omega| per particle (confinement)
  std::vector<Eigen::Vector3f> build_position_;  // positions at the last list build (skin)
  std::vector<float> lambda_;                // multiplier applied by the next delta-p pass
  // Sum of the multipliers applied so far in this step (kept by each particle across steps:
  // the warm start of the next).
  std::vector<float> lambda_sum_;
  std::vector<float> complementarity_residual_;  // warm start: what is left to correct
  float lambda_sum_dt_ = 0.0f;               // dt of the step lambda_sum_ belongs to
  std::vector<float> scorr_scale_;          // per particle bound of the s_corr push
  std::vector<float> pair_gradient_;         // per neighbour entry, lambda -> delta p pass (Jacobi)
  std::vector<float> image_gradient_;        // same for the image pairs by one wall
  std::vector<float> gradient_rows_;         // the sweep's per-thread rows of the same
  std::size_t gradient_row_length_ = 0;      // of each row, set with the sweep's order
  std::vector<std::uint8_t> has_coincident_pair_;  // per particle, lambda -> delta p pass
  std::vector<Eigen::Vector3f> wall_gradient_;  // solids' part of grad C, lambda -> delta p
  std::vector<float> density_;
  std::vector<std::uint16_t> neighbor_count_;
  // The free surface's lend of each particle (FreeSurfaceLend.h), kept across steps and
  // lowered by each step's first constraint pass; FreeSurfaceLend::kUnmeasured before it.
  std::vector<float> surface_lend_;
  std::unique_ptr<FreeSurfaceLend> surface_lend_table_;  // while the option is on
  bool surface_lend_set_ = false;  // this attempt's first pass has updated surface_lend_
  // Backups to reject a non-finite step: everything a step changes.
  std::vector<Eigen::Vector3f> saved_position_, saved_velocity_;
  std::vector<std::uint32_t> saved_id_;
  std::vector<float> saved_density_, saved_lambda_sum_, saved_surface_lend_;
  std::vector<std::uint16_t> saved_neighbor_count_;
  // Scratch for reorder() (swapped with the arrays it permutes).
  std::vector<Eigen::Vector3f> reorder_scratch_;
  std::vector<std::uint32_t> reorder_id_scratch_;
  std::vector<float> reorder_float_scratch_;

  std::unique_ptr<NeighborGrid> grid_;
  std::unique_ptr<BlockColours> colours_;  // of the grid's last build (Gauss-Seidel order)
  bool colours_valid_ = false;
  std::vector<double> chunk_compression_;  // the stop test's sum per deterministicSum chunk,
  std::vector<double> chunk_residual_;     // the sweep's residual per chunk,
  std::vector<std::uint32_t> chunk_order_;  // and the order it measures them in
  std::vector<float> sweep_residual_;     // each constraint's compression when projected
  std::unique_ptr<ChebyshevAcceleration> chebyshev_;  // of the constraint iterations
  std::unique_ptr<LatticeBoundary> lattice_;  // wall density for the current d and h
  // Positions (and lambda, velocities) in 16-byte slots for the wide neighbour sums.
  std::unique_ptr<PackedSlots> packed_;
  Eigen::AlignedBox3f fluid_reach_;  // empty: every obstacle takes part
  bool track_wrenches_ = false;
  WrenchAccumulator wrench_sums_;  // of the attempt in progress
  SolidWrenches wrenches_;         // of the last step
  bool lists_valid_ = false;
  bool attempt_too_dense_ = false;  // the last attempt's neighbour search hit neighborPairBound()
  float current_dt_ = 0.0f;  // dt of the attempt in progress (s_corr scales with it)
  double time_ = 0.0;
  std::uint64_t step_count_ = 0;
};

}  // namespace pbf
