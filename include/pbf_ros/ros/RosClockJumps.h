#pragma once
// Notices ROS time jumping while the node stamps its messages from it (on another node's
// /clock, without ~publish_clock). Plain (times are passed in, in seconds) so it is
// unit-tested.
//
// The stamps are the ROS time at which the simulation (re)started plus the simulated time
// since. A /clock that restarts (a bag played with --loop, a simulator reset) or leaps ahead
// left them far from ROS time: a probe's clock jumped to 1e9 s while the stamps stayed near
// 500, where no tf listener could use them. A jump is ROS time going back, or going forward
// by more than kLeap times the wall time elapsed (and at least kMinLeap seconds): a clock
// faster than the wall, a simulator at 5x real time, is not a jump.

namespace pbf_ros {

class RosClockJumps {
 public:
  static constexpr double kLeap = 10.0;
  static constexpr double kMinLeap = 1.0;  // [s]

  // ROS time and steady wall time now [s]. Returns by how much ROS time jumped beyond what
  // the wall clock explains (negative: back), 0 when it did not jump.
  double update(double ros_now, double wall_now) {
    double jump = 0.0;
    if (seen_) {
      const double ros_step = ros_now - last_ros_, wall_step = wall_now - last_wall_;
      if (ros_step < 0.0 || ros_step > kMinLeap + kLeap * wall_step) jump = ros_step - wall_step;
    }
    seen_ = true;
    last_ros_ = ros_now;
    last_wall_ = wall_now;
    return jump;
  }

 private:
  bool seen_ = false;
  double last_ros_ = 0.0, last_wall_ = 0.0;
};

}  // namespace pbf_ros
