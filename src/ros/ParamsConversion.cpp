#include "pbf_ros/ros/ParamsConversion.h"

#include <boost/any.hpp>
#include <cmath>
#include <sstream>

#include "pbf_ros/ros/RenderCameraParams.h"

namespace pbf_ros {

void solverParamsToConfig(const pbf::SolverParams& p, FluidConfig& c) {
  c.particle_spacing = p.particle_spacing;
  c.rest_density = p.rest_density;
  c.support_radius_factor = p.support_radius_factor;
  c.max_nan_retries = p.max_nan_retries;
  c.max_speed_factor = p.max_speed_factor;
  c.gravity_x = p.gravity.x();
  c.gravity_y = p.gravity.y();
  c.gravity_z = p.gravity.z();
  c.time_step = p.time_step;
  c.adaptive_time_step = p.adaptive_time_step;
  c.cfl_factor = p.cfl_factor;
  c.min_time_step = p.min_time_step;
  c.max_time_step = p.max_time_step;
  c.min_iterations = p.min_iterations;
  c.max_iterations = p.max_iterations;
  c.density_tolerance = p.density_tolerance;
  c.cfm_relaxation = p.cfm_relaxation;
  c.unilateral_constraint = p.unilateral_constraint;
  c.free_surface_lend = p.free_surface_lend;
  c.warm_start = p.warm_start;
  c.chebyshev_rho = p.chebyshev_rho;
  c.gauss_seidel = p.gauss_seidel;
  c.gauss_seidel_omega = p.gauss_seidel_omega;
  c.wall_density = p.wall_density;
  c.wall_friction = p.wall_friction;
  c.scorr_k = p.scorr_k;
  c.scorr_n = p.scorr_n;
  c.scorr_delta_q = p.scorr_delta_q;
  c.xsph_viscosity = p.xsph_viscosity;
  c.vorticity_epsilon = p.vorticity_epsilon;
  c.neighbor_skin = p.neighbor_skin;
}

pbf::SolverParams configToSolverParams(const FluidConfig& c, pbf::SolverParams base) {
  pbf::SolverParams& p = base;
  p.particle_spacing = static_cast<float>(c.particle_spacing);
  p.rest_density = static_cast<float>(c.rest_density);
  p.support_radius_factor = static_cast<float>(c.support_radius_factor);
  p.max_nan_retries = c.max_nan_retries;
  p.max_speed_factor = static_cast<float>(c.max_speed_factor);
  p.gravity = Eigen::Vector3f(static_cast<float>(c.gravity_x), static_cast<float>(c.gravity_y),
                              static_cast<float>(c.gravity_z));
  p.time_step = static_cast<float>(c.time_step);
  p.adaptive_time_step = c.adaptive_time_step;
  p.cfl_factor = static_cast<float>(c.cfl_factor);
  p.min_time_step = static_cast<float>(c.min_time_step);
  p.max_time_step = static_cast<float>(c.max_time_step);
  p.min_iterations = c.min_iterations;
  p.max_iterations = c.max_iterations;
  p.density_tolerance = static_cast<float>(c.density_tolerance);
  p.cfm_relaxation = static_cast<float>(c.cfm_relaxation);
  p.unilateral_constraint = c.unilateral_constraint;
  p.free_surface_lend = c.free_surface_lend;
  p.warm_start = c.warm_start;
  p.chebyshev_rho = static_cast<float>(c.chebyshev_rho);
  p.gauss_seidel = c.gauss_seidel;
  p.gauss_seidel_omega = static_cast<float>(c.gauss_seidel_omega);
  p.wall_density = c.wall_density;
  p.wall_friction = static_cast<float>(c.wall_friction);
  p.scorr_k = static_cast<float>(c.scorr_k);
  p.scorr_n = static_cast<float>(c.scorr_n);
  p.scorr_delta_q = static_cast<float>(c.scorr_delta_q);
  p.xsph_viscosity = static_cast<float>(c.xsph_viscosity);
  p.vorticity_epsilon = static_cast<float>(c.vorticity_epsilon);
  p.neighbor_skin = static_cast<float>(c.neighbor_skin);
  return p;
}

namespace {

// Copies one parameter between configs through its description (the generated code offers
// no typed setter by name).
void copyParam(const FluidConfig::AbstractParamDescriptionConstPtr& desc, const FluidConfig& from,
               FluidConfig& to) {
  dynamic_reconfigure::Config msg;
  desc->toMessage(msg, from);
  desc->fromMessage(msg, to);
}

template <typename T>
T valueOf(const FluidConfig::AbstractParamDescriptionConstPtr& desc, const FluidConfig& config) {
  boost::any value;
  desc->getValue(config, value);
  return boost::any_cast<T>(value);
}

}  // namespace

std::vector<std::string> rangeEndNotes(const FluidConfig& config, const FluidConfig& in_force) {
  std::vector<std::string> notes;
  const FluidConfig& min = FluidConfig::__getMin__();
  const FluidConfig& max = FluidConfig::__getMax__();
  auto note = [&](const auto& desc, auto value, auto lo, auto hi) {
    std::ostringstream text;
    text << desc->name << " = " << value << " is the " << (value == lo ? "lower" : "upper")
         << " end of its range [" << lo << ", " << hi
         << "]: requests beyond it are clamped to it before the node sees them";
    notes.push_back(text.str());
  };
  for (const auto& desc : FluidConfig::__getParamDescriptions__()) {
    if (desc->type == "double") {
      const double value = valueOf<double>(desc, config), lo = valueOf<double>(desc, min),
                   hi = valueOf<double>(desc, max);
      if (value != valueOf<double>(desc, in_force) && (value == lo || value == hi)) note(desc, value, lo, hi);
    } else if (desc->type == "int") {
      const int value = valueOf<int>(desc, config), lo = valueOf<int>(desc, min), hi = valueOf<int>(desc, max);
      if (value != valueOf<int>(desc, in_force) && (value == lo || value == hi)) note(desc, value, lo, hi);
    }
  }
  return notes;
}

std::vector<std::string> sanitizeConfig(FluidConfig& config, const FluidConfig& in_force) {
  std::vector<std::string> notes;
  const FluidConfig& min = FluidConfig::__getMin__();
  const FluidConfig& max = FluidConfig::__getMax__();
  for (const auto& desc : FluidConfig::__getParamDescriptions__()) {
    std::ostringstream note;
    if (desc->type == "double") {
      const double value = valueOf<double>(desc, config);
      if (!std::isfinite(value)) {
        copyParam(desc, in_force, config);
        note << desc->name << ": " << value << " is not a finite number; refused, keeping "
             << valueOf<double>(desc, config);
      } else if (value < valueOf<double>(desc, min) || value > valueOf<double>(desc, max)) {
        desc->clamp(config, max, min);
        note << desc->name << ": " << value << " is outside [" << valueOf<double>(desc, min)
             << ", " << valueOf<double>(desc, max) << "]; clamped to "
             << valueOf<double>(desc, config);
      }
    } else if (desc->type == "int") {
      const int value = valueOf<int>(desc, config);
      if (value < valueOf<int>(desc, min) || value > valueOf<int>(desc, max)) {
        desc->clamp(config, max, min);
        note << desc->name << ": " << value << " is outside [" << valueOf<int>(desc, min)
             << ", " << valueOf<int>(desc, max) << "]; clamped to " << valueOf<int>(desc, config);
      }
    }
    if (!note.str().empty()) notes.push_back(note.str());
  }
  // An enum of Fluid.cfg that arrives as free text: an unknown filter is refused here, once,
  // rather than warned about at every later request while the server kept showing it.
  if (!knownRenderFilter(config.render_filter)) {
    notes.push_back("render_filter: '" + config.render_filter +
                    "' is not narrow_range, bilateral or none; refused, keeping '" + in_force.render_filter + "'");
    config.render_filter = in_force.render_filter;
  }
  // gauss_seidel replaces the Jacobi solve that warm_start, chebyshev_rho and scorr_k act on.
  // Whichever side this request turned on wins, with a note (a checkbox in rqt is expected to
  // work); when it turned on both, the solver's own check refuses the request.
  const bool warm_on = config.warm_start, cheb_on = config.chebyshev_rho > 0.0,
             scorr_on = config.scorr_k > 0.0;
  if (config.gauss_seidel && (warm_on || cheb_on || scorr_on)) {
    const bool gauss_seidel_turned_on = !in_force.gauss_seidel;
    const bool jacobi_turned_on = (warm_on && !in_force.warm_start) ||
                                  (cheb_on && !(in_force.chebyshev_rho > 0.0)) ||
                                  (scorr_on && !(in_force.scorr_k > 0.0));
    const std::string jacobi_names = std::string(warm_on ? "warm_start " : "") +
                                     (cheb_on ? "chebyshev_rho " : "") + (scorr_on ? "scorr_k " : "");
    if (jacobi_turned_on && !gauss_seidel_turned_on) {
      config.gauss_seidel = false;
      notes.push_back("gauss_seidel: turned off, since " + jacobi_names + "act on the Jacobi solve");
    } else if (gauss_seidel_turned_on && !jacobi_turned_on) {
      config.warm_start = false;
      config.chebyshev_rho = 0.0;
      config.scorr_k = 0.0;
      notes.push_back(jacobi_names + "turned off, since gauss_seidel replaces the Jacobi solve they act on");
    }
  }
  // min_iterations 0 is the solve's own floor: SolverParams says which.
  pbf::SolverParams solve;
  solve.min_iterations = config.min_iterations;
  solve.gauss_seidel = config.gauss_seidel;
  const int least_iterations = solve.minIterations();
  if (least_iterations > config.max_iterations) {
    notes.push_back("max_iterations: " + std::to_string(config.max_iterations) +
                    " is below min_iterations; raised to " + std::to_string(least_iterations));
    config.max_iterations = least_iterations;
  }
  if (config.min_time_step > config.max_time_step) {
    std::ostringstream note;
    note << "min_time_step: " << config.min_time_step << " is above max_time_step; lowered to "
         << config.max_time_step;
    notes.push_back(note.str());
    config.min_time_step = config.max_time_step;
  }
  return notes;
}

void overlayParams(const FluidConfig& from, const std::set<std::string>& names,
                   FluidConfig& to) {
  for (const auto& desc : FluidConfig::__getParamDescriptions__()) {
    if (names.count(desc->name)) copyParam(desc, from, to);
  }
}

std::set<std::string> changedParams(const FluidConfig& a, const FluidConfig& b) {
  std::set<std::string> names;
  for (const auto& desc : FluidConfig::__getParamDescriptions__()) {
    std::uint32_t level = 0;
    desc->calcLevel(level, a, b);  // ORs in the parameter's level bit when values differ
    if (level != 0) names.insert(desc->name);
  }
  return names;
}

std::vector<std::string> configParamNames() {
  std::vector<std::string> names;
  for (const auto& desc : FluidConfig::__getParamDescriptions__()) names.push_back(desc->name);
  return names;
}

}  // namespace pbf_ros
