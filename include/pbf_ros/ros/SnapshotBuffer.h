#pragma once
// Hand-over of particle state from the simulation thread to a consumer thread (the surface
// renderer) without ever blocking the solver: the simulation writes into a spare snapshot
// and swaps it in; a reader holds its snapshot by shared_ptr for as long as it likes.
//
// Copies cost time, so the simulation writes only while some consumer asks for snapshots
// (setRequestedRate > 0), at most at that rate.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

namespace pbf {
class PbfSolver;
}

namespace pbf_ros {

struct ParticleSnapshot {
  std::uint64_t version = 0;        // increases with every write; equal = nothing changed
  double stamp = 0.0;               // header stamp of the state [s]
  double sim_time = 0.0;            // since the last reset [s]
  std::uint64_t step_count = 0;
  Eigen::AlignedBox3f container;    // in fluid_domain
  float particle_spacing = 0.0f;    // [m]
  std::vector<Eigen::Vector3f> positions;        // fluid_domain [m]
  // Small = surface particle. uint32 (the solver keeps uint16) because that is what
  // pbf::FluidRenderer::render takes: the widening happens in this copy, not in the renderer.
  std::vector<std::uint32_t> neighbor_counts;
};

class SnapshotBuffer {
 public:
  // --- consumer side (any thread) ---
  // How often the consumer wants fresh snapshots [Hz]; 0 = none (no copies are made).
  void setRequestedRate(double hz) { requested_rate_.store(hz); }
  double requestedRate() const { return requested_rate_.load(); }
  // Latest snapshot, or null before the first write. Never waits for the solver.
  std::shared_ptr<const ParticleSnapshot> latest() const;

  // --- producer side (simulation thread) ---
  // Copies the solver state into the spare buffer and makes it the latest.
  void write(const pbf::PbfSolver& solver, double stamp, double sim_time);

 private:
  std::atomic<double> requested_rate_{0.0};
  mutable std::mutex mutex_;                  // guards latest_ (a pointer swap, nothing more)
  std::shared_ptr<ParticleSnapshot> latest_;
  std::shared_ptr<ParticleSnapshot> spare_;   // producer only
  std::uint64_t version_ = 0;                 // producer only
};

}  // namespace pbf_ros
