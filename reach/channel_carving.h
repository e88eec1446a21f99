#pragma once
// Bathymetry for a terrain that shows the water surface instead of the bed. Airborne LiDAR does
// not see through water, so a DEM's river is often a flat strip at the level of the day it was
// flown. carve_channel lowers the bed to a trapezoidal channel along a centreline: at distance d
// from the centreline the channel's surface is bottom + max(0, d - bottom_width / 2) /
// side_slope, the bottom lying `depth` below the terrain sampled on the centreline (linear
// between its points), and the bed becomes the lower of the two. What it assumes: one channel
// of constant cross-section, its bottom following the terrain's own fall along the centreline,
// and a bank line at the terrain where the two meet.

#include "reach/grid.h"
#include "reach/reach_config.h"

namespace reach {

// Lowers `bed` (NaN cells stay closed); returns the number of cells lowered.
long carve_channel(const Grid& grid, Field& bed, const ChannelConfig& channel);

}  // namespace reach
