// FluidConfig <-> SolverParams, and the checks on user input (clamp, refuse non-finite).
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>

#include "pbf_ros/ros/ParamsConversion.h"

using pbf_ros::FluidConfig;

namespace {
bool mentions(const std::vector<std::string>& notes, const std::string& word) {
  return std::any_of(notes.begin(), notes.end(),
                     [&](const std::string& n) { return n.find(word) != std::string::npos; });
}
}  // namespace

TEST(ParamsConversion, RoundTripKeepsEverySolverField) {
  pbf::SolverParams p;
  p.particle_spacing = 0.03f;
  p.gravity = Eigen::Vector3f(1.0f, -2.0f, -3.0f);
  p.xsph_viscosity = 0.002f;
  p.vorticity_epsilon = 0.05f;
  p.min_iterations = 3;
  p.max_iterations = 7;
  p.adaptive_time_step = false;
  p.unilateral_constraint = false;
  p.free_surface_lend = false;  // not the default: the round trip must carry it
  p.warm_start = true;
  p.chebyshev_rho = 0.9f;
  p.gauss_seidel = false;  // not the default: the round trip must carry it
  p.gauss_seidel_omega = 1.6f;
  p.wall_density = false;
  p.wall_friction = 0.4f;
  p.scorr_k = 0.1f;
  p.neighbor_skin = 0.3f;
  FluidConfig c = FluidConfig::__getDefault__();
  pbf_ros::solverParamsToConfig(p, c);
  const pbf::SolverParams q = pbf_ros::configToSolverParams(c);
  EXPECT_FLOAT_EQ(q.particle_spacing, 0.03f);
  EXPECT_TRUE(q.gravity.isApprox(p.gravity));
  EXPECT_FLOAT_EQ(q.xsph_viscosity, 0.002f);
  EXPECT_FLOAT_EQ(q.vorticity_epsilon, 0.05f);
  EXPECT_EQ(q.min_iterations, 3);
  EXPECT_EQ(q.max_iterations, 7);
  EXPECT_FALSE(q.adaptive_time_step);
  EXPECT_FALSE(q.unilateral_constraint);
  EXPECT_FALSE(q.free_surface_lend);
  EXPECT_TRUE(q.warm_start);
  EXPECT_FLOAT_EQ(q.chebyshev_rho, 0.9f);
  EXPECT_FALSE(q.gauss_seidel);
  EXPECT_FLOAT_EQ(q.gauss_seidel_omega, 1.6f);
  EXPECT_FALSE(q.wall_density);
  EXPECT_FLOAT_EQ(q.wall_friction, 0.4f);
  EXPECT_FLOAT_EQ(q.scorr_k, 0.1f);
  EXPECT_FLOAT_EQ(q.neighbor_skin, 0.3f);
}

TEST(ParamsConversion, DefaultsMatchTheSolverDefaults) {
  // Fluid.cfg's defaults and SolverParams' defaults must not drift apart.
  const pbf::SolverParams from_cfg = pbf_ros::configToSolverParams(FluidConfig::__getDefault__());
  const pbf::SolverParams solver;
  EXPECT_FLOAT_EQ(from_cfg.particle_spacing, solver.particle_spacing);
  EXPECT_FLOAT_EQ(from_cfg.xsph_viscosity, solver.xsph_viscosity);
  EXPECT_FLOAT_EQ(from_cfg.cfm_relaxation, solver.cfm_relaxation);
  EXPECT_EQ(from_cfg.gauss_seidel, solver.gauss_seidel);
  EXPECT_FLOAT_EQ(from_cfg.gauss_seidel_omega, solver.gauss_seidel_omega);
  EXPECT_EQ(from_cfg.max_iterations, solver.max_iterations);
  EXPECT_TRUE(from_cfg.gravity.isApprox(solver.gravity));
  EXPECT_EQ(from_cfg.validate(), "");
}

TEST(ParamsConversion, NonFiniteValuesAreRefusedAndTheValueInForceKept) {
  FluidConfig in_force = FluidConfig::__getDefault__();
  in_force.xsph_viscosity = 0.0005;
  FluidConfig request = in_force;
  request.xsph_viscosity = std::numeric_limits<double>::quiet_NaN();
  request.gravity_x = std::numeric_limits<double>::infinity();
  const auto notes = pbf_ros::sanitizeConfig(request, in_force);
  EXPECT_DOUBLE_EQ(request.xsph_viscosity, 0.0005);
  EXPECT_DOUBLE_EQ(request.gravity_x, in_force.gravity_x);
  EXPECT_TRUE(mentions(notes, "xsph_viscosity"));
  EXPECT_TRUE(mentions(notes, "gravity_x"));
  EXPECT_TRUE(mentions(notes, "refused"));
}

// A filter name that is none of Fluid.cfg's choices (dynparam takes free text) is refused
// once; it stayed on the server and was warned about at every later request (a probe).
TEST(ParamsConversion, AnUnknownRenderFilterIsRefusedAndTheFilterInForceKept) {
  FluidConfig in_force = FluidConfig::__getDefault__();
  in_force.render_filter = "bilateral";
  FluidConfig request = in_force;
  request.render_filter = "gaussian";
  auto notes = pbf_ros::sanitizeConfig(request, in_force);
  EXPECT_EQ(request.render_filter, "bilateral");
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_EQ(notes[0], "render_filter: 'gaussian' is not narrow_range, bilateral or none; refused, keeping 'bilateral'");
  notes = pbf_ros::sanitizeConfig(request, in_force);  // the next request: nothing to say
  EXPECT_TRUE(notes.empty());
}

TEST(ParamsConversion, OutOfRangeValuesAreClampedWithANote) {
  FluidConfig in_force = FluidConfig::__getDefault__();
  FluidConfig request = in_force;
  request.gravity_z = -1.0e6;
  request.max_iterations = 100000;
  const auto notes = pbf_ros::sanitizeConfig(request, in_force);
  EXPECT_DOUBLE_EQ(request.gravity_z, FluidConfig::__getMin__().gravity_z);
  EXPECT_EQ(request.max_iterations, FluidConfig::__getMax__().max_iterations);
  EXPECT_TRUE(mentions(notes, "gravity_z"));
  EXPECT_TRUE(mentions(notes, "clamped"));
}

TEST(ParamsConversion, InconsistentPairsAreFixed) {
  FluidConfig c = FluidConfig::__getDefault__();
  c.min_iterations = 9;
  c.max_iterations = 3;
  c.min_time_step = 0.01;
  c.max_time_step = 0.001;
  const auto notes = pbf_ros::sanitizeConfig(c, FluidConfig::__getDefault__());
  EXPECT_EQ(c.max_iterations, 9);
  EXPECT_DOUBLE_EQ(c.min_time_step, c.max_time_step);
  EXPECT_EQ(notes.size(), 2u);
  EXPECT_EQ(pbf_ros::configToSolverParams(c).validate(), "");
}

// gauss_seidel replaces the Jacobi solve that warm_start, chebyshev_rho and scorr_k act on:
// what the request turned on wins, with a note; turning on both is left to the solver's
// check, which refuses it.
TEST(ParamsConversion, SolverChoiceFollowsWhatTheRequestTurnedOn) {
  const FluidConfig gauss_seidel = FluidConfig::__getDefault__();
  ASSERT_TRUE(gauss_seidel.gauss_seidel);
  FluidConfig c = gauss_seidel;
  c.warm_start = true;
  c.chebyshev_rho = 0.9;
  auto notes = pbf_ros::sanitizeConfig(c, gauss_seidel);
  EXPECT_FALSE(c.gauss_seidel);
  EXPECT_TRUE(c.warm_start);
  EXPECT_TRUE(mentions(notes, "gauss_seidel: turned off"));
  EXPECT_EQ(pbf_ros::configToSolverParams(c).validate(), "");

  const FluidConfig jacobi = c;
  c.gauss_seidel = true;
  notes = pbf_ros::sanitizeConfig(c, jacobi);
  EXPECT_TRUE(c.gauss_seidel);
  EXPECT_FALSE(c.warm_start);
  EXPECT_DOUBLE_EQ(c.chebyshev_rho, 0.0);
  EXPECT_TRUE(mentions(notes, "warm_start chebyshev_rho turned off"));
  EXPECT_EQ(pbf_ros::configToSolverParams(c).validate(), "");

  c = FluidConfig::__getDefault__();
  c.gauss_seidel = false;
  const FluidConfig plain_jacobi = c;
  c.gauss_seidel = true;
  c.scorr_k = 0.1;
  pbf_ros::sanitizeConfig(c, plain_jacobi);
  EXPECT_TRUE(c.gauss_seidel && c.scorr_k > 0.0) << "both turned on: left as asked";
  EXPECT_NE(pbf_ros::configToSolverParams(c).validate().find("gauss_seidel replaces"), std::string::npos);
}

TEST(ParamsConversion, SaneConfigHasNoNotes) {
  FluidConfig c = FluidConfig::__getDefault__();
  EXPECT_TRUE(pbf_ros::sanitizeConfig(c, c).empty());
}

TEST(ParamsConversion, OverlayCopiesOnlyTheNamedParameters) {
  FluidConfig user = FluidConfig::__getDefault__();
  user.particle_spacing = 0.05;
  user.xsph_viscosity = 0.003;
  FluidConfig scene = FluidConfig::__getDefault__();
  scene.particle_spacing = 0.01;
  scene.xsph_viscosity = 0.0;
  pbf_ros::overlayParams(user, {"particle_spacing", "not_a_parameter"}, scene);
  EXPECT_DOUBLE_EQ(scene.particle_spacing, 0.05);
  EXPECT_DOUBLE_EQ(scene.xsph_viscosity, 0.0);
}

TEST(ParamsConversion, ChangedParamsNamesExactlyTheDifferences) {
  FluidConfig a = FluidConfig::__getDefault__();
  FluidConfig b = a;
  EXPECT_TRUE(pbf_ros::changedParams(a, b).empty());
  b.xsph_viscosity = 0.005;
  b.scene = "other";
  b.unilateral_constraint = !a.unilateral_constraint;
  EXPECT_EQ(pbf_ros::changedParams(a, b),
            (std::set<std::string>{"xsph_viscosity", "scene", "unilateral_constraint"}));
}

namespace {
// `config` with one parameter set to its value in `bound` (Fluid.cfg's min or max).
FluidConfig withBound(const FluidConfig::AbstractParamDescriptionConstPtr& desc,
                      const FluidConfig& bound) {
  FluidConfig config = FluidConfig::__getDefault__();
  dynamic_reconfigure::Config msg;
  desc->toMessage(msg, bound);
  desc->fromMessage(msg, config);
  // min_iterations at its max (100) needs max_iterations 100 too: sanitizeConfig's rule.
  pbf_ros::sanitizeConfig(config, FluidConfig::__getDefault__());
  return config;
}
}  // namespace

TEST(ParamsConversion, EveryAdvertisedRangeEndIsUsable) {
  // What Fluid.cfg offers (rqt's sliders, dynparam) the solver must accept: scorr_delta_q's
  // advertised minimum 0 used to be refused by the solver.
  // One exception, on purpose: particle_spacing's range starts at 0, where the solver refuses
  // it by name, because the server clamps a request to the range before the node sees it
  // (a typed -1 must arrive as something the node refuses, not as a fine spacing).
  for (const auto& desc : FluidConfig::__getParamDescriptions__()) {
    for (const FluidConfig* bound : {&FluidConfig::__getMin__(), &FluidConfig::__getMax__()}) {
      const FluidConfig config = withBound(desc, *bound);
      const std::string invalid = pbf_ros::configToSolverParams(config).validate();
      if (desc->name == "particle_spacing" && bound == &FluidConfig::__getMin__()) {
        EXPECT_NE(invalid.find("particle_spacing must be a finite number > 0"), std::string::npos) << invalid;
        continue;
      }
      EXPECT_EQ(invalid, "") << desc->name << " at its " << (bound == &FluidConfig::__getMin__() ? "min" : "max");
    }
  }
}

// The server clamps a request to Fluid.cfg's range before the node sees it: a changed value
// at an end of its range is named with the range, one untouched at an end is not.
TEST(ParamsConversion, ChangedValuesAtAnEndOfTheirRangeAreNamed) {
  FluidConfig in_force = FluidConfig::__getDefault__();
  in_force.max_speed_factor = FluidConfig::__getMin__().max_speed_factor;  // set earlier, not now
  FluidConfig request = in_force;
  request.gravity_z = FluidConfig::__getMin__().gravity_z;       // -1e9 asked, -100 arrives
  request.render_width = FluidConfig::__getMax__().render_width;  // 100000 asked, 4096 arrives
  request.xsph_viscosity = 0.0001;                                // inside its range
  const auto notes = pbf_ros::rangeEndNotes(request, in_force);
  ASSERT_EQ(notes.size(), 2u);
  EXPECT_TRUE(mentions(notes, "gravity_z = -100 is the lower end of its range [-100, 100]"));
  EXPECT_TRUE(mentions(notes, "render_width = 4096 is the upper end of its range"));
  EXPECT_FALSE(mentions(notes, "max_speed_factor"));
  EXPECT_TRUE(pbf_ros::rangeEndNotes(in_force, in_force).empty());
}
