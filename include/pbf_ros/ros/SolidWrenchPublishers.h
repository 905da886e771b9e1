#pragma once
// ~wrench/<name> (geometry_msgs/WrenchStamped): the fluid's force and torque on each solid,
// averaged over the simulated time since the topic's previous message (a single step's
// value jitters with the particles), published at ~wrench_rate [Hz, wall clock] to the
// topics someone subscribes to. wanted() asks the solver to measure only while one of these
// topics has a subscriber (or ~track_wrenches is true); a scene's floating bodies turn
// measuring on for themselves (FloatingBodies::prepare). Otherwise wrenches cost nothing.
// Simulation thread only.

#include <map>
#include <string>
#include <vector>

#include <ros/ros.h>

#include "pbf_ros/core/PbfSolver.h"
#include "pbf_ros/ros/SolidWrenchTargets.h"

namespace pbf_ros {

class SolidWrenchPublishers {
 public:
  SolidWrenchPublishers(ros::NodeHandle pnh, double rate, bool always_track);

  // A new scene: advertises its targets' topics; topics no longer in it are shut down.
  void setTargets(std::vector<WrenchTarget> targets);
  // Whether the next step should measure wrenches.
  bool wanted() const;
  // After a step the solver tracked: adds its wrenches, weighted by `dt`.
  void accumulate(const pbf::Scene& scene, const pbf::PbfSolver& solver, double dt);
  // Publishes the averages when due; clears every sum.
  void publishDue(double wall, const ros::Time& stamp);
  // Average over every solid together (fluid_domain, about its origin) since the last call,
  // for ~stats; false when no step was measured since.
  bool takeTotal(pbf::Wrench& total);

 private:
  struct Topic {
    WrenchTarget target;
    pbf::Wrench sum;      // integral over time [N s], [N m s]
    double seconds = 0.0;
  };

  ros::NodeHandle pnh_;
  double period_;
  bool always_track_;
  double next_wall_ = 0.0;
  std::vector<Topic> topics_;
  std::map<std::string, ros::Publisher> publishers_;  // by name, kept across scenes
  pbf::Wrench total_sum_;
  double total_seconds_ = 0.0;
};

}  // namespace pbf_ros
