#pragma once
// Where pbf_node's robot comes from: a URDF on the parameter server and which of its links
// become fluid solids. Read again at every rebuild (start, ~reset, scene switch), so a new
// URDF on the parameter server is picked up then.
//
// Node parameters (private, read at start-up):
//   ~robot_description_param  name of the parameter holding the URDF, resolved in the node's
//                             namespace like robot_state_publisher does (default
//                             "robot_description"; "" = no robot)
//   ~robot_links              list of link names (default: every link with collision geometry)
//   ~robot_link_regex         ECMAScript regex on whole link names (default: all)
//   ~robot_tf_wait            [wall s] how long the first build waits for the links' tf

#include <string>
#include <vector>

#include <ros/node_handle.h>

#include "pbf_ros/ros/UrdfSolids.h"

namespace pbf_ros {

struct RobotSource {
  std::string description_param = "robot_description";  // "" = no robot
  bool param_named = false;  // the user named it: its absence is then an error, not "no robot"
  std::vector<std::string> links;
  std::string link_regex;
  double tf_wait = 5.0;

  bool enabled() const { return !description_param.empty(); }
};

// Reads the settings above from `pnh`. Throws std::runtime_error naming a parameter of the
// wrong type (e.g. ~robot_links given as a string).
RobotSource readRobotSource(const ros::NodeHandle& pnh);

struct RobotLoad {
  bool found = false;       // a URDF string was on the parameter server
  std::string param;        // the parameter's resolved name, for messages
  UrdfSolids robot;         // its solids and one line per problem
};

// The solids of one robot link in a scene: indices into Scene::obstacles (the node appends
// them after the scene file's own obstacles).
struct RobotLinkSolids {
  std::string link;
  std::vector<std::size_t> obstacles;
  std::size_t left_out = 0;  // solids not added (no tf for the link)
};

// Fetches the URDF from the parameter server now (`nh`: the node's namespace) and turns the
// selected links into solids with mesh grids of cell = spacing / 2 and band = support
// radius + spacing. Never throws for bad input: what is wrong is in robot.problems.
RobotLoad loadRobot(const RobotSource& source, const ros::NodeHandle& nh, float spacing,
                    float support_radius);

}  // namespace pbf_ros
