#pragma once
// The pipeline's first step: the request checked and every trajectory's parameters drawn and split.

#include <vector>

#include "sph/generation/generation.h"
#include "sph/scene/scene_loader.h"

namespace sph {

// Checks the request, draws every trajectory's parameters from the seed (all before anything
// runs, so a resumed or repeated generation draws the same ones) and assigns the splits. Loads
// every drawn scene, so a missing scene file or a bad pointer throws ConfigError (naming the file
// and the pointer) before anything is simulated or written. Throws common::InputError for bad
// counts.
std::vector<TrajectoryPlan> plan_trajectories(const GenerateOptions& options);

// The scene of one trajectory: the scene file with options.overrides, then the drawn parameters.
LoadedScene trajectory_scene(const GenerateOptions& options, const nlohmann::json& parameters);

}  // namespace sph
