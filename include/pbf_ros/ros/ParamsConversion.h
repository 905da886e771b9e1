#pragma once
// pbf_ros::FluidConfig (dynamic_reconfigure) <-> pbf::SolverParams. Plain functions, unit-
// tested without a master. This is where user input is checked: out-of-range values are
// clamped, non-finite values are refused (the value in force is kept), and every such
// decision is returned as a note that names the parameter.

#include <set>
#include <string>
#include <vector>

#include <pbf_ros/FluidConfig.h>

#include "pbf_ros/core/SolverParams.h"

namespace pbf_ros {

// Writes every solver field of `config` from `params` (scene values seed the server).
// Node-level fields (scene, rates, real-time factor) are left untouched.
void solverParamsToConfig(const pbf::SolverParams& params, FluidConfig& config);

// Reads the solver fields of `config` over `base` (no checking). Fields Fluid.cfg does not
// have keep base's value, so a scene's settings survive for them.
pbf::SolverParams configToSolverParams(const FluidConfig& config,
                                       pbf::SolverParams base = pbf::SolverParams());

// Makes `config` usable, in place:
//  - a non-finite number is refused: the field takes its value from `in_force` (the config
//    currently applied), with a note;
//  - a value outside the range of config/Fluid.cfg is clamped to it, with a note;
//  - gauss_seidel with warm_start, chebyshev_rho or scorr_k (Jacobi-only options): the side
//    `config` turned on relative to `in_force` wins, the other is turned off;
//  - a render_filter that is none of Fluid.cfg's choices is refused (`in_force`'s is kept);
//  - min_iterations (or its floor, when 0) > max_iterations raises max_iterations,
//    min_time_step > max_time_step lowers min_time_step;
//  each with a note.
// Returns the notes (empty when the config was already fine).
std::vector<std::string> sanitizeConfig(FluidConfig& config, const FluidConfig& in_force);

// Notes on the numbers `config` changes from `in_force` to an end of their Fluid.cfg range.
// The reconfigure server clamps a request to that range before the node sees it, so a value
// at an end may stand for one beyond it (a typed -1 arrives as the range's minimum): say so,
// naming the range. Empty when no changed value sits at an end.
std::vector<std::string> rangeEndNotes(const FluidConfig& config, const FluidConfig& in_force);

// Copies the parameters named in `names` from `from` into `to` (explicit user overrides on
// top of a scene's values). Unknown names are ignored.
void overlayParams(const FluidConfig& from, const std::set<std::string>& names,
                   FluidConfig& to);

// Names of the parameters whose values differ between a and b.
std::set<std::string> changedParams(const FluidConfig& a, const FluidConfig& b);

// Names of every parameter of config/Fluid.cfg.
std::vector<std::string> configParamNames();

}  // namespace pbf_ros
