#pragma once
// The checks of a scene as a whole, after each of its parts has checked itself while it was read:
// frames and time steps that fit, parts that need a terrain, geometry inside /domain, a size the
// machine can hold (scene_size.h), outlets that can carry their rates and emitters inside the
// geometry. Needs the terrain grid loaded. Throws ConfigError naming the file and the pointer.

#include <string>

#include "sph/scene/scene.h"

namespace sph {

void check_scene(const SceneConfig& scene, const std::string& file);

}  // namespace sph
