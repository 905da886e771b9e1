#include "bench/BenchScenes.h"

namespace pbf_bench {

std::string defaultScenesDir() { return std::string(PBF_SOURCE_DIR) + "/config/scenes"; }

pbf::Scene damBreakScene(const std::string& scenes_dir, float spacing, float depth) {
  pbf::Scene s = pbf::loadSceneFile(pbf::resolveScenePath("dam_break", scenes_dir));
  s.solver.particle_spacing = spacing;
  if (depth > 0.0f) {
    s.container.max().y() = s.container.min().y() + depth;
    for (auto& b : s.fluid) b.max.y() = std::min(b.max.y(), s.container.max().y());
  }
  const std::string err = s.validate();
  if (!err.empty()) throw pbf::SceneError("dam break at spacing " + std::to_string(spacing) + ": " + err);
  return s;
}

float damBreakWidth(const pbf::Scene& scene) {
  return scene.fluid.at(0).max.x() - scene.fluid.at(0).min.x();
}

pbf::Scene hydrostaticScene(const std::string& scenes_dir, float spacing) {
  pbf::Scene s = pbf::loadSceneFile(pbf::resolveScenePath("hydrostatic_tank", scenes_dir));
  s.solver.particle_spacing = spacing;
  const std::string err = s.validate();
  if (!err.empty()) throw pbf::SceneError("hydrostatic tank at spacing " + std::to_string(spacing) + ": " + err);
  return s;
}

pbf::Scene sloshingScene(float spacing) {
  pbf::Scene s;
  s.name = "sloshing_tank";
  s.container = Eigen::AlignedBox3f(Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(0.8f, 0.2f, 0.5f));
  pbf::FluidBlock low, high;
  low.min = Eigen::Vector3f(0.0f, 0.0f, 0.0f);
  low.max = Eigen::Vector3f(0.4f, 0.2f, 0.15f);
  high.min = Eigen::Vector3f(0.4f, 0.0f, 0.0f);
  high.max = Eigen::Vector3f(0.8f, 0.2f, 0.3f);
  s.fluid = {low, high};
  s.solver.particle_spacing = spacing;
  return s;
}

}  // namespace pbf_bench
