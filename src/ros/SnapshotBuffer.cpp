#include "pbf_ros/ros/SnapshotBuffer.h"

#include "pbf_ros/core/PbfSolver.h"

namespace pbf_ros {

std::shared_ptr<const ParticleSnapshot> SnapshotBuffer::latest() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return latest_;
}

void SnapshotBuffer::write(const pbf::PbfSolver& solver, double stamp, double sim_time) {
  // Reuse the spare buffer unless a reader still holds it (then it stays theirs).
  if (!spare_ || spare_.use_count() > 1) spare_ = std::make_shared<ParticleSnapshot>();
  ParticleSnapshot& s = *spare_;
  s.version = ++version_;
  s.stamp = stamp;
  s.sim_time = sim_time;
  s.step_count = solver.stepCount();
  s.container = solver.container();
  s.particle_spacing = solver.params().particle_spacing;
  s.positions = solver.positions();        // assignment reuses capacity
  const auto& counts = solver.neighborCounts();
  s.neighbor_counts.assign(counts.begin(), counts.end());
  {
    std::lock_guard<std::mutex> lock(mutex_);
    std::swap(latest_, spare_);
  }
}

}  // namespace pbf_ros
