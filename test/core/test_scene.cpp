// Scene files: the shipped ones load; bad ones say which file, which key, what was expected.

#include <gtest/gtest.h>

#include <filesystem>

#include "pbf_ros/core/Scene.h"

namespace {

const std::string kScenes = std::string(PBF_SOURCE_DIR) + "/config/scenes";

std::string errorOf(const std::string& yaml) {
  try {
    pbf::loadSceneString(yaml, "bad.yaml");
  } catch (const pbf::SceneError& e) {
    return e.what();
  }
  return "";
}

TEST(Scene, EveryShippedSceneLoadsAndFillsParticlesInsideItsContainer) {
  int count = 0;
  for (const auto& e : std::filesystem::directory_iterator(kScenes)) {
    if (e.path().extension() != ".yaml") continue;
    const pbf::Scene s = pbf::loadSceneFile(e.path().string());
    std::vector<Eigen::Vector3f> x, v;
    s.initialParticles(x, v);
    EXPECT_GT(x.size(), 500u) << e.path();
    for (const auto& p : x) ASSERT_TRUE(s.container.contains(p)) << e.path();
    ++count;
  }
  EXPECT_GE(count, 4);
}

TEST(Scene, ParticleCountFollowsTheSpacing) {
  pbf::Scene s = pbf::loadSceneFile(kScenes + "/dam_break.yaml");
  std::vector<Eigen::Vector3f> x, v;
  s.initialParticles(x, v);
  EXPECT_EQ(x.size(), 20u * 25u * 40u);  // 0.4 x 0.5 x 0.8 m at 0.02 m
  s.solver.particle_spacing = 0.04f;
  s.initialParticles(x, v);
  EXPECT_EQ(x.size(), 10u * 12u * 20u);
}

TEST(Scene, DefaultsAreSI) {
  const pbf::Scene s = pbf::loadSceneFile(kScenes + "/hydrostatic_tank.yaml");
  EXPECT_FLOAT_EQ(s.solver.rest_density, 1000.0f);
  EXPECT_FLOAT_EQ(s.solver.supportRadius(), 2.0f * s.solver.particle_spacing);
  // The water of one lattice cell; the density sums use it normalised on the start lattice,
  // m / 1.2359 for h = 2d (LatticeBoundary.h).
  EXPECT_NEAR(s.solver.particleMass(), 1000.0f * std::pow(s.solver.particle_spacing, 3.0f),
              1e-6 * s.solver.particleMass());
  EXPECT_NEAR(s.solver.densityMass(), s.solver.particleMass() / 1.23589f, 1e-5 * s.solver.particleMass());
  EXPECT_FLOAT_EQ(s.solver.gravity.z(), -9.81f);
}

TEST(Scene, BadFilesNameFileKeyAndExpectation) {
  const std::string base = "container: {min: [0,0,0], max: [1,1,1]}\n";
  struct Case { std::string yaml, must_contain; };
  const std::vector<Case> cases = {
      {"container: {min: [0,0], max: [1,1,1]}\nfluid: [{box: {min: [0,0,0], max: [1,1,1]}}]",
       "key 'container.min': expected a list of 3 numbers"},
      {base + "fluid: [{box: {min: [0,0,0], max: [0.5,x,0.5]}}]", "key 'fluid[0].box.max[1]': expected a number"},
      {base + "fluid: []", "key 'fluid': expected a non-empty list"},
      {base + "fluid: [{cone: {}}]", "unknown key 'fluid[0].cone'"},
      {base + "fluid: [{box: {min: [0,0,0], max: [2,1,1]}}]", "fluid[0] reaches outside the container"},
      {base + "fluid: [{box: {min: [0,0,0], max: [1,1,1]}}]\nsolver: {xsph: 0.1}", "unknown solver parameter 'solver.xsph'"},
      {base + "fluid: [{box: {min: [0,0,0], max: [1,1,1]}}]\nsolver: {max_iterations: many}", "key 'solver.max_iterations': expected an integer"},
      {base + "fluid: [{box: {min: [0,0,0], max: [1,1,1]}}]\nsolver: {xsph_viscosity: 5}", "xsph_viscosity must be in [0, 1]"},
      {base + "fluid: [{box: {min: [0,0,0], max: [1,1,1]}}]\nsolver: {scorr_delta_q: 0.6}",
       "scorr_delta_q must be in (0, 0.5] (a fraction of h, at most the rest spacing"},
      {base + "fluid: [{box: {min: [0,0,0], max: [1,1,1]}}]\nsolver: {vorticity_epsilon: 30}",
       "vorticity_epsilon must be in [0, 5] 1/s (beyond, confinement outgrows"},
      {base + "fluid: [{box: {min: [0,0,0], max: [1,1,1]}}]\nsolver: {chebyshev_rho: 1}", "chebyshev_rho must be in [0, 0.99]"},
      {base + "fluid: [{box: {min: [0,0,0], max: [1,1,1]}}]\n"
              "solver: {gauss_seidel: false, warm_start: true, unilateral_constraint: false}",
       "warm_start needs the one-sided constraint"},
      {base + "fluid: [{box: {min: [0,0,0], max: [1,1,0.5]}}]\n"
              "obstacles: [{sphere: {center: [0.5,0.5,0.8], radius: 0.001}, dynamic: {density: 100000}}]",
       "floating obstacle 0: its mass 0.000418879 kg is less than one fluid particle's"},
      {base + "fluid: [{box: {min: [0,0,0], max: [1,1,0.5]}}]\n"
              "obstacles: [{sphere: {center: [0.5,0.5,0.8], radius: 0.1}, dynamic: {density: 500, inertia: [1e-9, 1, 1e-9]}}]",
       "inertia [1e-09, 1, 1e-09] kg m^2 is no body's"},
      {base + "fluid: [{box: {min: [0,0,0], max: [1,1,0.5]}}]\n"
              "obstacles: [{sphere: {center: [0.5,0.5,0.8], radius: 0.1}, dynamic: {mass: 100, inertia: [1e-9, 1e-9, 1e-9]}}]",
       "inertia [1e-09, 1e-09, 1e-09] kg m^2 is below [0.000335103, 0.000335103, 0.000335103], the solid's at 2 %"},
      {base + "fluid: [{box: {min: [0,0,0], max: [1,1,1]}}]\nsolver: {warm_start: often}", "key 'solver.warm_start'"},
      {"fluid: [{box: {min: [0,0,0], max: [1,1,1]}}]", "key 'container': expected to be present"},
      {"[1, 2", "not valid YAML"},
  };
  for (const auto& c : cases) {
    const std::string err = errorOf(c.yaml);
    EXPECT_NE(err.find("bad.yaml"), std::string::npos) << err;
    EXPECT_NE(err.find(c.must_contain), std::string::npos) << "got: " << err;
  }
}

// s_corr's |dq| is bounded by the rest spacing, which is a fraction of h that depends on
// the support: 0.6 h is too far at h = 2d and within the spacing at h = 1.5d.
TEST(Scene, ScorrDeltaQIsBoundedByTheRestSpacing) {
  pbf::SolverParams p;
  p.scorr_delta_q = 0.5f;
  EXPECT_EQ(p.validate(), "");
  p.scorr_delta_q = 0.6f;
  EXPECT_NE(p.validate().find("scorr_delta_q must be in (0, 0.5]"), std::string::npos) << p.validate();
  p.support_radius_factor = 1.5f;
  EXPECT_EQ(p.validate(), "");
}

TEST(Scene, UnknownSceneNameListsTheKnownOnes) {
  try {
    pbf::resolveScenePath("no_such_scene", kScenes);
    FAIL();
  } catch (const pbf::SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("dam_break"), std::string::npos) << e.what();
  }
  EXPECT_EQ(pbf::resolveScenePath("dam_break", kScenes), kScenes + "/dam_break.yaml");
  EXPECT_THROW(pbf::loadSceneFile("/nonexistent/x.yaml"), pbf::SceneError);
}

TEST(Scene, SolverYamlIsAllOrNothing) {
  pbf::SolverParams p;
  EXPECT_THROW(pbf::applySolverYaml("{xsph_viscosity: 0.002, max_iterations: -3}", "params", p), pbf::SceneError);
  EXPECT_FLOAT_EQ(p.xsph_viscosity, pbf::SolverParams().xsph_viscosity);
  pbf::applySolverYaml("{xsph_viscosity: 0.002, gravity: [0, 0, -1]}", "params", p);
  EXPECT_FLOAT_EQ(p.xsph_viscosity, 0.002f);
  EXPECT_FLOAT_EQ(p.gravity.z(), -1.0f);
}

// min_iterations 0 (the default) is the solve's own floor: one Gauss-Seidel sweep, two
// Jacobi corrections. Asking the Jacobi solve for max_iterations 1 alone says which
// parameter to set as well.
TEST(Scene, FewerIterationsThanTheSolvesFloorNameIt) {
  pbf::SolverParams p;
  pbf::applySolverYaml("{max_iterations: 1}", "params", p);
  EXPECT_EQ(p.max_iterations, 1);
  EXPECT_EQ(p.minIterations(), 1);
  try {
    pbf::applySolverYaml("{gauss_seidel: false, max_iterations: 1}", "params", p);
    FAIL() << "max_iterations below the Jacobi solve's floor was accepted";
  } catch (const pbf::SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("min_iterations 0 means 2 for the Jacobi solve"), std::string::npos)
        << e.what();
  }
  EXPECT_TRUE(p.gauss_seidel) << "a refused setting must leave the parameters as they were";
  // min_iterations given: the message says what it is, not what 0 would mean.
  try {
    pbf::applySolverYaml("{min_iterations: 100, max_iterations: 1}", "params", p);
    FAIL() << "min_iterations above max_iterations was accepted";
  } catch (const pbf::SceneError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("got min_iterations 100, max_iterations 1)"), std::string::npos) << m;
    EXPECT_EQ(m.find("means"), std::string::npos) << m;
  }
  pbf::applySolverYaml("{gauss_seidel: false, min_iterations: 1, max_iterations: 1}", "params", p);
  EXPECT_EQ(p.max_iterations, 1);
  EXPECT_EQ(p.minIterations(), 1);
}

TEST(Scene, DynamicObstaclesFloatWithTheirMassAndPublishedFrame) {
  const std::string head =
      "container: {min: [0, 0, 0], max: [1, 1, 1]}\n"
      "fluid: [{box: {min: [0, 0, 0], max: [1, 1, 0.5]}}]\n"
      "solver: {particle_spacing: 0.05}\n";
  const pbf::Scene s = pbf::loadSceneString(
      head + "obstacles:\n"
             "  - {box: {center: [0.5, 0.5, 0.5], half_extents: [0.1, 0.1, 0.05]}, dynamic: {density: 500}}\n"
             "  - {frame: ball, sphere: {center: [0.2, 0.2, 0.8], radius: 0.05},\n"
             "     dynamic: {mass: 2.0, inertia: [0.01, 0.02, 0.03]}}\n"
             "  - {box: {center: [0.8, 0.8, 0.2], half_extents: [0.05, 0.05, 0.05]}}\n",
      "floating.yaml");
  ASSERT_EQ(s.floating.size(), 2u);
  EXPECT_EQ(s.floating[0].obstacle, 0u);
  EXPECT_NEAR(s.floating[0].mass, 500.0 * 0.2 * 0.2 * 0.1, 1e-6);
  EXPECT_EQ(s.obstacles[0].frame, "floating_0");  // the frame the node publishes it on
  EXPECT_TRUE(s.obstacles[0].offset.isApprox(Eigen::Isometry3f::Identity()));
  EXPECT_TRUE(s.obstacles[0].pose.translation().isApprox(Eigen::Vector3f(0.5f, 0.5f, 0.5f)));
  EXPECT_EQ(s.obstacles[1].frame, "ball");
  EXPECT_DOUBLE_EQ(s.floating[1].mass, 2.0);
  EXPECT_NEAR(s.floating[1].inertia(2, 2), 0.03, 1e-7);
  EXPECT_TRUE(s.floats(1));
  EXPECT_FALSE(s.floats(2));
  EXPECT_NE(errorOf(head + "obstacles: [{sphere: {center: [0.5, 0.5, 0.5], radius: 0.1}, dynamic: {mass: 1, density: 2}}]\n")
                .find("obstacles[0].dynamic"),
            std::string::npos);
  EXPECT_NE(errorOf(head + "obstacles: [{sphere: {center: [0.5, 0.5, 0.5], radius: 0.1}, dynamic: {density: -5}}]\n")
                .find("positive"),
            std::string::npos);
  EXPECT_NE(errorOf(head + "obstacles: [{sphere: {center: [0.5, 0.5, 0.5], radius: 0.1}, dynamic: {mass: 1, inertia: [1, 0, 1]}}]\n")
                .find("inertia"),
            std::string::npos);
}

}  // namespace
