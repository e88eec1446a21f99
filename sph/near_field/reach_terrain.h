#pragma once
// The terrain, water and inflow of a near field inside a reach run (terrain source "reach"): the
// box of ReachWindowConfig sampled from the run (reach/near_field_window.h) into the frame river
// scenes use. x runs with the flow from the box's upstream end, y towards the left bank, and z is
// the elevation less the reach's water level at the inflow section, so the water surface there is
// z = 0 as in the built-in river. The reach's wet cells are the water mask, and the inflow speed
// is the reach's depth-averaged velocity through that section (discharge over area): the SPH
// inflow enters as one plug across the section (sph/river/river_flow.h), at the reach's mean.
// The box's two sides (along the flow, so along streamlines) are walls: their outermost nodes
// rise to the deepest water's depth above the level where the bank is lower.

#include <string>

#include "sph/river/river_configs.h"
#include "sph/river/terrain.h"

namespace sph {

struct ReachNearField {
  Terrain terrain;
  Real speed = 0;      // m/s along +x through the inflow section
  double level = 0;    // the reach's water level there (map elevation of z = 0)
  double heading = 0;  // compass bearing of +x (the one given, or the flow's)
  double time = 0;     // the reach output used (s)
};

// `config.run` resolved already; `inflow_x` is where the inflow's level and speed are taken.
// Throws ConfigError naming `scene_file` and `pointer` + the key (see sample_near_field).
ReachNearField near_field_from_reach(const ReachWindowConfig& config, Real inflow_x,
                                     const std::string& scene_file, const std::string& pointer);

}  // namespace sph
