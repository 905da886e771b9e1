#include "pbf_ros/ros/RealTimePacer.h"

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

void RealTimePacer::afterStep(double wall, double sim) {
  if (factor_ > 0.0) {
    const double target = anchor_sim_ + factor_ * (wall - anchor_wall_);
    const double debt_wall = (target - sim) / factor_;
    if (debt_wall > max_lag_) {
      // Behind by more than we are willing to catch up: forget the debt, keep going from
      // here, and remember it so the achieved factor is reported, not hidden.
      dropped_sim_time_ += target - sim;
      anchor_wall_ = wall;
      anchor_sim_ = sim;
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
