#pragma once
// The scenes the validation and stress tools run, built from the shipped scene files so
// that what we validate is what users run. Variations (resolution, tank depth, sloshing)
// are made here in code rather than in extra YAML files the node would list.

#include <string>

#include "pbf_ros/core/Scene.h"

namespace pbf_bench {

// config/scenes of the source tree (overridable for installed use).
std::string defaultScenesDir();

// config/scenes/dam_break.yaml (a = 0.4 m column, 2a high, Martin & Moyce n^2 = 2) at the
// given spacing. depth > 0 narrows the tank and column across y (the flow is uniform
// across y between free-slip walls, so a narrower slab changes cost, not the front).
pbf::Scene damBreakScene(const std::string& scenes_dir, float spacing, float depth = 0.0f);

// Column width a of a dam-break scene (its first fluid block's extent along x).
float damBreakWidth(const pbf::Scene& scene);

// config/scenes/hydrostatic_tank.yaml at the given spacing.
pbf::Scene hydrostaticScene(const std::string& scenes_dir, float spacing);

// A sloshing tank: 0.8 x 0.2 x 0.5 m, water 0.15 m deep on the left half and 0.3 m on the
// right (a tilted free surface as two blocks), so it sloshes back and forth for a long time.
pbf::Scene sloshingScene(float spacing);

}  // namespace pbf_bench
