#pragma once
// The built-in river: a seeded terrain with the reaches a spill scenario needs, so that the
// default scenes need no external data. Water flows along +x and its surface is z = 0. From
// upstream: a straight inflow reach, a bend (the centreline swings `bend_amplitude` towards +y, the
// left bank, and back), a narrowing reach and a widening reach to the outflow, each a quarter of
// the length with smooth transitions. The cross-section is trapezoidal: a flat bed `depth` below
// the surface, banks of slope `bank_slope` (horizontal per vertical) rising to `bank_height`
// above it, and a flat floodplain beyond; the bed carries a seeded roughness. The water mask
// marks where the bed lies below the surface.

#include <string>
#include <utility>
#include <vector>

#include "sph/river/river_configs.h"
#include "sph/river/terrain.h"

namespace sph {

Terrain generate_river(const RiverGeneratorConfig& config);

// The terms of the grid's half width across the flow (its span is twice their sum), each named by
// the setting it comes from: the bend, half the widest surface, the bank, the floodplain. The
// scene size check blames the largest one for a grid too large to generate.
std::vector<std::pair<std::string, Real>> river_half_span_terms(const RiverGeneratorConfig& config);

// Where the generated river's centreline is and how wide it is at the surface, at x.
Real river_centreline_y(const RiverGeneratorConfig& config, Real x);
Real river_surface_width(const RiverGeneratorConfig& config, Real x);

}  // namespace sph
