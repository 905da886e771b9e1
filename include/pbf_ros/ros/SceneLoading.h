#pragma once
// Finding and checking a scene by name or path, as the node does at start-up, on
// reconfigure and on reset.

#include <string>

#include "pbf_ros/core/Scene.h"

namespace pbf_ros {

// config/scenes of the installed package ("" when the package cannot be found).
std::string defaultScenesDir();

// Resolves, parses and validates a scene. Throws pbf::SceneError naming the file and
// what is wrong.
pbf::Scene loadScene(const std::string& name_or_path, const std::string& scenes_dir);

}  // namespace pbf_ros
