#pragma once
// Turns a pipeline leak (LeakConfig) into the emitter that releases its oil: a disc of the
// opening's radius, `height` above the water surface over the chosen point of the channel,
// pointing down. Oil poured onto the surface, as in the vessel pour scene, rather than released
// under water: an emitter inside the water would place its particles on top of water particles.

#include <string>

#include "sph/boundary/boundary_configs.h"
#include "sph/river/river_configs.h"
#include "sph/river/terrain.h"

namespace sph {

// Throws ConfigError (naming `file` and /leaks/<index>) when the pipeline crosses no water or the
// point under the opening is dry.
EmitterConfig leak_emitter(const LeakConfig& leak, const Terrain& terrain, Real water_level,
                           const std::string& file, size_t index);

}  // namespace sph
