#pragma once
// The picture of a reach's flow at one moment, for a person to read alone: the terrain as a
// hillshade, the water's depth in blues, velocity arrows, and a band below with the time, a
// scale bar in metres, north and a legend of the depth colours and the arrow length.

#include <string>

#include "common/image_writer.h"
#include "reach/shallow_water.h"

namespace reach {

// Where a reach's map lies in its picture: what draw_reach_map draws for a grid and width.
struct MapFrame {
  double metres_per_pixel = 1;
  int width = 0, height = 0;  // the map's pixels; the picture's band lies below `height`
  int band_top = 0, band_height = 0;
  double x0 = 0, y0 = 0;  // the grid's south-west corner
  // Pixels from the picture's top-left corner of map point (x, y).
  void to_pixel(double x, double y, double& px, double& py) const {
    px = (x - x0) / metres_per_pixel;
    py = height - (y - y0) / metres_per_pixel;
  }
};
MapFrame reach_map_frame(const Grid& grid, int max_width = 1000);

// At most `max_width` pixels wide (a cell is one or more whole pixels, or cells are sampled
// when the grid is wider). `depth_scale` (m): the depth drawn darkest; `speed_scale` (m/s): the
// speed of the longest arrow; both fixed over a run so its pictures compare.
common::RgbImage draw_reach_map(const Grid& grid, const Field& bed, const WaterState& water,
                                double time_s, double depth_scale, double speed_scale,
                                double dry_depth, int max_width = 1000);

// "t = 1 h 05 min 30 s" style, from seconds.
std::string duration_label(double seconds);

}  // namespace reach
