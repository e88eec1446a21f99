#pragma once
// The spill metrics (sph/river/spill_metrics.h) of a simulation: which scenes have them and how a
// frame is measured, shared by `spill-sim run`, the dataset pipeline and the learned models'
// scores.

#include <memory>

#include "sph/river/spill_metrics.h"
#include "sph/scene/scene.h"
#include "sph/simulation/simulation.h"

namespace sph {

// The spill metrics of a scene with a leak over terrain, measured from the most upstream leak;
// nullptr for other scenes.
std::unique_ptr<SpillMetrics> river_spill_metrics(const SceneConfig& scene);
// Measures the simulation's current frame (its oil released so far from its emitters).
void measure_spill(SpillMetrics& spill, const Simulation& sim);

}  // namespace sph
