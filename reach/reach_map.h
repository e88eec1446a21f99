#pragma once
// The picture of a reach's flow at one moment, for a person to read alone: the terrain as a
// hillshade, the water's depth in blues, velocity arrows, and a band below with the time, a
// scale bar in metres, north and a legend of the depth colours and the arrow length.

#include <string>

#include "common/image_writer.h"
#include "reach/shallow_water.h"

namespace reach {

// At most `max_width` pixels wide (a cell is one or more whole pixels, or cells are sampled
// when the grid is wider). `depth_scale` (m): the depth drawn darkest; `speed_scale` (m/s): the
// speed of the longest arrow; both fixed over a run so its pictures compare.
common::RgbImage draw_reach_map(const Grid& grid, const Field& bed, const WaterState& water,
                                double time_s, double depth_scale, double speed_scale,
                                double dry_depth, int max_width = 1000);

// "t = 1 h 05 min 30 s" style, from seconds.
std::string duration_label(double seconds);

}  // namespace reach
