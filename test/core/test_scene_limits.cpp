// Hostile scene input (issue 11): every failure is a SceneError naming the file and the key,
// floats that only a double can hold are refused, files and block counts are bounded, and
// the particle count is checked without allocating the particles.

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "pbf_ros/core/Scene.h"

namespace {

const std::string kBox = "container: {min: [0,0,0], max: [1,1,1]}\n";
const std::string kFluid = "fluid: [{box: {min: [0,0,0], max: [0.5,0.5,0.5]}}]\n";

// The SceneError's message, or "" when the text loads. Any other exception fails the test.
std::string errorOf(const std::string& yaml) {
  try {
    pbf::loadSceneString(yaml, "bad.yaml");
  } catch (const pbf::SceneError& e) {
    return e.what();
  }
  return "";
}

TEST(SceneLimits, NonStringNamesAndKeysAreNamedRefusals) {
  // yaml-cpp's own exceptions (bad conversion) used to escape the loader.
  const std::string list_name = errorOf("name: [a, b]\n" + kBox + kFluid);
  EXPECT_NE(list_name.find("bad.yaml: key 'name': expected a string"), std::string::npos) << list_name;
  const std::string list_key = errorOf(kBox + kFluid + "? [a, b]\n: 1\n");
  EXPECT_NE(list_key.find("bad.yaml"), std::string::npos) << list_key;
  EXPECT_NE(list_key.find("not a plain name"), std::string::npos) << list_key;
  const std::string solver_key = errorOf(kBox + kFluid + "solver: {? {a: 1} : 2}\n");
  EXPECT_NE(solver_key.find("under 'solver.'"), std::string::npos) << solver_key;
}

TEST(SceneLimits, FloatOverflowIsRefusedNotTurnedIntoInf) {
  const std::string err =
      errorOf(kBox + kFluid + "domain_pose: {translation: [1e39, 0, 0]}\n");
  EXPECT_NE(err.find("key 'domain_pose.translation[0]': expected a finite number"),
            std::string::npos)
      << err;
}

TEST(SceneLimits, TooManyBlocksAreRefusedByCount) {
  std::string yaml = kBox + "fluid:\n";
  for (std::size_t i = 0; i <= pbf::kMaxFluidBlocks; ++i)
    yaml += "  - {box: {min: [0,0,0], max: [0.1,0.1,0.1]}}\n";
  const std::string err = errorOf(yaml);
  EXPECT_NE(err.find("key 'fluid': expected at most 1000 blocks (got 1001)"), std::string::npos)
      << err;
}

TEST(SceneLimits, DirectoriesDevicesAndHugeFilesAreNotScenes) {
  const std::string dir = testing::TempDir();
  try {
    pbf::loadSceneFile(dir);
    FAIL();
  } catch (const pbf::SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("is a directory"), std::string::npos) << e.what();
  }
  try {
    pbf::resolveScenePath("/dev/zero", dir);
    FAIL();
  } catch (const pbf::SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("not a regular file"), std::string::npos) << e.what();
  }
  try {
    pbf::loadSceneFile("/dev/zero");  // would read forever
    FAIL();
  } catch (const pbf::SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("not a regular file"), std::string::npos) << e.what();
  }
  const std::string big = dir + "/pbf_big_scene.yaml";
  {
    std::ofstream out(big);
    out << kBox << kFluid << "# " << std::string(pbf::kMaxSceneFileBytes, 'x') << "\n";
  }
  try {
    pbf::loadSceneFile(big);
    FAIL();
  } catch (const pbf::SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("may have at most 1048576 bytes"), std::string::npos)
        << e.what();
  }
  std::remove(big.c_str());
}

TEST(SceneLimits, ParticleCountIsCheckedWithoutBuildingTheParticles) {
  pbf::Scene s = pbf::loadSceneString(kBox + kFluid, "ok.yaml");
  s.solver.particle_spacing = 0.05f;  // 10 x 10 x 10
  EXPECT_EQ(s.checkParticleCount(1000), "");
  EXPECT_NE(s.checkParticleCount(999).find("needs more than 999"), std::string::npos);
  // 1e-4 m: 1.25e11 lattice points. Refused from the bound (walking them would take hours,
  // storing them terabytes).
  s.solver.particle_spacing = 1e-4f;
  const std::string err = s.checkParticleCount(1000000);
  EXPECT_NE(err.find("needs about 1.25e+11 particles"), std::string::npos) << err;
}

TEST(SceneLimits, ObstaclesThatRemoveEveryParticleAreReported) {
  const pbf::Scene s = pbf::loadSceneString(
      kBox + kFluid + "obstacles: [{box: {center: [0.25,0.25,0.25], half_extents: [0.3,0.3,0.3]}}]\n",
      "covered.yaml");
  EXPECT_NE(s.checkParticleCount(1000000).find("obstacles cover every fluid block"),
            std::string::npos);
}

TEST(SceneLimits, BlocksFollowTheirFrameOrTheContainerFrame) {
  const pbf::Scene s = pbf::loadSceneString(
      kBox + "container_frame: tank\nfluid:\n  - {box: {min: [0,0,0], max: [0.5,0.5,0.5]}}\n"
             "  - {frame: cup, box: {min: [0.5,0.5,0.5], max: [0.9,0.9,0.9]}}\n",
      "frames.yaml");
  EXPECT_EQ(s.blockFrame(0), "tank");
  EXPECT_EQ(s.blockFrame(1), "cup");
  std::vector<Eigen::Vector3f> x, v;
  std::vector<std::uint32_t> block_of;
  s.initialParticles(x, v, &block_of);
  ASSERT_EQ(block_of.size(), x.size());
  EXPECT_EQ(block_of.front(), 0u);
  EXPECT_EQ(block_of.back(), 1u);
}

}  // namespace
