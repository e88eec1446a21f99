#include "reach/channel_carving.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace reach {

namespace {

// The terrain at map point (x, y): the nearest cell's value (NaN outside the grid).
double sample(const Grid& g, const Field& bed, double x, double y) {
  const int i = int(std::floor((x - g.x0) / g.dx)), j = int(std::floor((y - g.y0) / g.dy));
  if (i < 0 || j < 0 || i >= g.nx || j >= g.ny) return std::nan("");
  return bed[g.at(i, j)];
}

}  // namespace

long carve_channel(const Grid& g, Field& bed, const ChannelConfig& c) {
  // The bottom's level at each centreline point, from the terrain before carving.
  std::vector<double> bottom;
  for (const auto& p : c.centreline) bottom.push_back(sample(g, bed, p[0], p[1]) - c.depth);
  const Field before = bed;
  long lowered = 0;
  const double half = 0.5 * c.bottom_width;
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      const size_t cell = g.at(i, j);
      if (std::isnan(before[cell])) continue;
      const double x = g.x(i), y = g.y(j);
      double best = std::numeric_limits<double>::infinity(), level = std::nan("");
      for (size_t k = 0; k + 1 < c.centreline.size(); ++k) {
        const double ax = c.centreline[k][0], ay = c.centreline[k][1];
        const double bx = c.centreline[k + 1][0], by = c.centreline[k + 1][1];
        const double len2 = (bx - ax) * (bx - ax) + (by - ay) * (by - ay);
        const double t =
            len2 > 0 ? std::clamp(((x - ax) * (bx - ax) + (y - ay) * (by - ay)) / len2, 0.0, 1.0)
                     : 0.0;
        const double d = std::hypot(x - (ax + t * (bx - ax)), y - (ay + t * (by - ay)));
        if (d < best && !std::isnan(bottom[k]) && !std::isnan(bottom[k + 1])) {
          best = d;
          level = bottom[k] + t * (bottom[k + 1] - bottom[k]);
        }
      }
      if (std::isnan(level)) continue;
      double surface;
      if (best <= half)
        surface = level;
      else if (c.side_slope > 0)
        surface = level + (best - half) / c.side_slope;
      else
        continue;
      if (surface < bed[cell]) {
        bed[cell] = surface;
        ++lowered;
      }
    }
  return lowered;
}

}  // namespace reach
