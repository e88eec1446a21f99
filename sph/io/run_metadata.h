#pragma once
// metadata.json of a run folder (the data contract, docs/design.md): dimension, frame interval,
// bounds, radii, gravity, solver and kernel, particle counts and types, and the resolved scene.
// `spill-sim run` writes it beside trajectory.h5; a generated dataset's metadata.json starts
// from it.

#include <nlohmann/json.hpp>

#include "sph/scene/scene_loader.h"
#include "sph/simulation/simulation.h"

namespace sph {

// `frames`: the frames recorded after the first (sequence_length is frames + 1).
nlohmann::json run_metadata(const Simulation& sim, const LoadedScene& scene, int frames);

}  // namespace sph
