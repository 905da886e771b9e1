#pragma once
// Paces simulated time against wall time at a requested real-time factor, and measures the
// factor actually achieved. Plain (times are passed in, in seconds) so it is unit-tested.
// "Wall" is whichever clock paces: the node passes another node's /clock when it follows
// one (FluidNode::pacingNow), and the factor is then simulated seconds per clock second.
//
// Sim time follows wall time: the simulation steps while it is behind
//   target(wall) = anchor_sim + factor * (wall - anchor_wall).
// When it cannot keep up, it does not try to catch up forever: once the debt exceeds
// max_lag of wall time, the anchor moves to "now" (the debt is dropped) and the dropped
// time is counted. achievedFactor() then tells the truth about the speed reached.
// On another node's /clock the debt is counted in clock seconds, and a coarse clock (a bag
// played at 20x ticks 0.2 s at a time) hands over a tick's worth at once, which is no sign of
// falling behind: there (setLagByDuration) the debt is dropped only once the simulation has
// been behind for max_lag of wall time without a break and the clock has ticked on since:
// a simulation that clears each tick's debt before the next tick keeps up, however coarse.
// And the latest tick's worth (at most kMaxTickKept) is kept: dropped too, the simulation
// would idle until the next tick, a quarter of a 0.2 s tick clock's time at half its speed.

#include <cstdint>
#include <deque>
#include <utility>

namespace pbf_ros {

class RealTimePacer {
 public:
  // max_lag: wall seconds of debt tolerated before it is dropped; window: wall seconds over
  // which the achieved factor is measured.
  explicit RealTimePacer(double max_lag = 0.1, double window = 2.0);

  // 0 = as fast as possible. Negative or non-finite values are treated as 1.
  void setFactor(double factor);
  double factor() const { return factor_; }

  // Starts pacing afresh from (wall, sim): after start-up, resume, reset or a factor change.
  // Forgets the measurement window.
  void restart(double wall, double sim);

  // True when a step should be taken now.
  bool shouldStep(double wall, double sim) const;
  // Wall time at which `sim` is due (when to wake up); wall itself when factor is 0.
  double wallTimeDue(double sim) const;

  // Records a step that ended at (wall, sim); drops excessive debt. `steady_wall` is the
  // wall clock, for how long the debt has lasted (setLagByDuration); by default `wall`.
  void afterStep(double wall, double sim) { afterStep(wall, sim, wall); }
  void afterStep(double wall, double sim, double steady_wall);
  void setLagByDuration(bool on) { lag_by_duration_ = on; }
  static constexpr double kMaxTickKept = 1.0;  // [clock s] beyond, a tick is a leap
  // The simulated time due at `wall` (the pacing clock).
  double targetSim(double wall) const { return anchor_sim_ + factor_ * (wall - anchor_wall_); }

  // Simulated seconds per wall second over the window (0 before two samples).
  double achievedFactor() const;
  // True once the samples span half a window: before that the factor is too noisy to judge
  // (the first steps after start or reset are slow: allocations, cold caches).
  bool settled() const;
  // True when debt was dropped within the last window: the requested factor is not reached.
  bool fallingBehind(double wall) const;
  // Simulated seconds that were not simulated because the simulation could not keep up.
  double droppedSimTime() const { return dropped_sim_time_; }

 private:
  double max_lag_;
  double window_;
  double factor_ = 1.0;
  double anchor_wall_ = 0.0;
  double anchor_sim_ = 0.0;
  double last_drop_wall_ = -1.0e300;
  double dropped_sim_time_ = 0.0;
  bool lag_by_duration_ = false;
  double behind_since_ = -1.0;  // steady wall time the current debt began; < 0: none
  double behind_clock_ = 0.0;   // the clock's reading then
  double last_clock_ = 0.0, last_tick_ = 0.0;  // the latest reading, and by how much it moved
  std::deque<std::pair<double, double>> samples_;  // (wall, sim)
};

}  // namespace pbf_ros
