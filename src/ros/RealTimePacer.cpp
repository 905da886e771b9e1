#include "pbf_ros/ros/RealTimePacer.h"

#include <algorithm>
#include <cmath>

namespace pbf_ros {

RealTimePacer::RealTimePacer(double max_lag, double window)
    : max_lag_(max_lag > 0.0 ? max_lag : 0.1), window_(window > 0.0 ? window : 2.0) {}

void RealTimePacer::setFactor(double factor) {
  factor_ = (std::isfinite(factor) && factor >= 0.0) ? factor : 1.0;
}

void RealTimePacer::restart(double wall, double sim) {
  anchor_wall_ = wall;
  anchor_sim_ = sim;
  behind_since_ = -1.0;
  last_clock_ = wall;
  last_tick_ = 0.0;
  samples_.clear();
  samples_.emplace_back(wall, sim);
}

bool RealTimePacer::shouldStep(double wall, double sim) const {
  if (factor_ <= 0.0) return true;
  return sim < anchor_sim_ + factor_ * (wall - anchor_wall_);
}

double RealTimePacer::wallTimeDue(double sim) const {
  if (factor_ <= 0.0) return anchor_wall_;
  return anchor_wall_ + (sim - anchor_sim_) / factor_;
}

void RealTimePacer::afterStep(double wall, double sim, double steady_wall) {
  if (factor_ > 0.0) {
    const double target = anchor_sim_ + factor_ * (wall - anchor_wall_);
    const double debt_wall = (target - sim) / factor_;
    bool drop = debt_wall > max_lag_;
    double keep = 0.0;  // of the debt, when it is dropped
    if (lag_by_duration_) {
      if (wall > last_clock_) last_tick_ = wall - last_clock_;
      last_clock_ = wall;
      keep = std::min(target - sim, factor_ * std::min(last_tick_, kMaxTickKept));
      if (debt_wall <= 0.0) {
        behind_since_ = -1.0;
      } else if (behind_since_ < 0.0) {
        behind_since_ = steady_wall;
        behind_clock_ = wall;
      }
      drop = behind_since_ >= 0.0 && steady_wall - behind_since_ > max_lag_ && wall > behind_clock_;
    }
    if (drop) {
      behind_since_ = -1.0;
      // Behind by more than we are willing to catch up: forget the debt, keep going from
      // here, and remember it so the achieved factor is reported, not hidden.
      dropped_sim_time_ += target - sim - keep;
      anchor_wall_ = wall;
      anchor_sim_ = sim + keep;
      last_drop_wall_ = wall;
    }
  }
  samples_.emplace_back(wall, sim);
  while (samples_.size() > 2 && wall - samples_[1].first >= window_) samples_.pop_front();
}

double RealTimePacer::achievedFactor() const {
  if (samples_.size() < 2) return 0.0;
  const double dwall = samples_.back().first - samples_.front().first;
  if (dwall <= 0.0) return 0.0;
  return (samples_.back().second - samples_.front().second) / dwall;
}

bool RealTimePacer::settled() const {
  return samples_.size() >= 2 && samples_.back().first - samples_.front().first >= 0.5 * window_;
}

bool RealTimePacer::fallingBehind(double wall) const {
  return factor_ > 0.0 && wall - last_drop_wall_ < window_;
}

}  // namespace pbf_ros
