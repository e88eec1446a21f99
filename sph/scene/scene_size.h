#pragma once
// What a scene will allocate, estimated from its settings alone, so that a scene too large for
// the machine is refused naming the key before anything is allocated. Without it a 1e9 m wide
// river overflowed an int while its height grid was sampled and crashed, and particle_radius 1e-4
// on the tank grew to 11 GB with no output.

#include <string>
#include <vector>

#include "common/memory_limit.h"
#include "sph/scene/scene.h"

namespace sph {

// Bytes of memory one particle takes, neighbour lists included: measured 730 B from the resident
// size of the tank (hydrostatic.json) at 56k and 148k particles. A floor, not a ceiling.
constexpr double kBytesPerParticle = 700;

// Refuses a generated river whose height grid cannot be held in `memory_bytes` or indexed by an
// int, naming the setting that makes it so large. Called before the grid is generated.
void check_river_grid_size(const RiverGeneratorConfig& river, const std::string& file,
                           const std::string& pointer, double memory_bytes);

// The particles one part of a scene allocates (fluid and boundary, an emitter's outlet and all
// it will release), estimated from its size and /particle_radius without allocating anything.
struct ScenePart {
  std::string pointer;  // e.g. /fluid_blocks/0, /terrain/fill_water, /leaks/1
  double particles;
};
std::vector<ScenePart> estimate_particles(const SceneConfig& scene);

// Refuses a scene whose particles (walls, terrain, fluid blocks, water fill, inflow reserve and
// emitter outlets, estimated from their sizes and /particle_radius) or neighbour grid cannot be
// held in `memory_bytes`, naming the part that holds the most. Needs the terrain grid loaded.
void check_scene_size(const SceneConfig& scene, const std::string& file, double memory_bytes);

}  // namespace sph
