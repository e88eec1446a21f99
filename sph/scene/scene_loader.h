#pragma once
// Loading a scene file: one pass that reads the JSON against SceneConfig's declarations, loads or
// generates the terrain grid and checks the scene as a whole (scene_checks.h), so that whatever a
// Simulation is given can be built. Errors are ConfigErrors naming the file and the JSON pointer.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "sph/scene/scene.h"

namespace sph {

// The default scene settings, with a section for every registered pressure solver and force.
SceneConfig default_scene();

struct LoadedScene {
  SceneConfig config;
  nlohmann::json resolved;  // every parameter, defaults filled in
  std::string file;
};

// Loads a scene file, applying `overrides` ("/json/pointer=value"; value parsed as JSON, or taken
// as a string when it is not JSON) before validation. Throws ConfigError naming file and pointer.
LoadedScene load_scene(const std::string& file, const std::vector<std::string>& overrides = {});

// Validates an in-memory scene (as load_scene does after parsing). `file` names it in errors.
LoadedScene parse_scene(nlohmann::json j, const std::string& file);

// The parameter reference of scene files as a Markdown table.
std::string scene_reference_markdown();

}  // namespace sph
