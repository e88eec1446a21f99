#include "reach/grid_sampling.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace reach {

double bilinear_valid(const Field& values, const Grid& g, double x, double y) {
  const double fx = (x - g.x0) / g.dx - 0.5, fy = (y - g.y0) / g.dy - 0.5;
  const int i0 = int(std::floor(fx)), j0 = int(std::floor(fy));
  const double tx = fx - i0, ty = fy - j0;
  double sum = 0, weight = 0;
  for (int dj = 0; dj < 2; ++dj)
    for (int di = 0; di < 2; ++di) {
      const int i = std::clamp(i0 + di, 0, g.nx - 1), j = std::clamp(j0 + dj, 0, g.ny - 1);
      const double v = values[g.at(i, j)];
      const double w = (di ? tx : 1 - tx) * (dj ? ty : 1 - ty);
      if (!std::isfinite(v) || w <= 0) continue;
      sum += w * v;
      weight += w;
    }
  return weight > 0 ? sum / weight : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace reach
