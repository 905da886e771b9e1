#include "pbf_ros/ros/SceneLoading.h"

#include <ros/package.h>

namespace pbf_ros {

std::string defaultScenesDir() {
  const std::string package = ros::package::getPath("pbf_ros");
  return package.empty() ? std::string() : package + "/config/scenes";
}

pbf::Scene loadScene(const std::string& name_or_path, const std::string& scenes_dir) {
  if (name_or_path.empty()) throw pbf::SceneError("scene: empty name; expected a scene name or path");
  const std::string path = pbf::resolveScenePath(name_or_path, scenes_dir);
  pbf::Scene scene = pbf::loadSceneFile(path);
  const std::string problem = scene.validate();
  if (!problem.empty()) throw pbf::SceneError(path + ": " + problem);
  return scene;
}

}  // namespace pbf_ros
