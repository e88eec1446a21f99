#include "sph/simulation/spill_measurement.h"

#include <algorithm>

namespace sph {

std::unique_ptr<SpillMetrics> river_spill_metrics(const SceneConfig& scene) {
  if (scene.leaks.empty() || !scene.terrain_grid) return nullptr;
  Real leak_x = scene.leaks[0].x;
  for (const auto& leak : scene.leaks) leak_x = std::min(leak_x, leak.x);
  return std::make_unique<SpillMetrics>(*scene.terrain_grid, scene.terrain->water_level, leak_x,
                                        scene.particle_diameter(), scene.watch_points);
}

void measure_spill(SpillMetrics& spill, const Simulation& sim) {
  double released = 0;
  for (const auto& e : sim.emitters()) released += e.oil_released();
  spill.measure(sim.fluid(), sim.time(), released);
}

}  // namespace sph
