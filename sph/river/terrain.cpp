#include "sph/river/terrain.h"

#include <algorithm>
#include <cmath>

namespace sph {

Real Terrain::height_at(Real x, Real y) const {
  const Real fx = std::clamp((x - origin_x) / cell_size, Real(0), Real(nx - 1));
  const Real fy = std::clamp((y - origin_y) / cell_size, Real(0), Real(ny - 1));
  const int ix = std::min(int(fx), nx - 2), iy = std::min(int(fy), ny - 2);
  const Real tx = fx - Real(ix), ty = fy - Real(iy);
  return (1 - tx) * (1 - ty) * at(ix, iy) + tx * (1 - ty) * at(ix + 1, iy) +
         (1 - tx) * ty * at(ix, iy + 1) + tx * ty * at(ix + 1, iy + 1);
}

bool Terrain::is_water(Real x, Real y) const {
  const long ix = std::lround((x - origin_x) / cell_size);
  const long iy = std::lround((y - origin_y) / cell_size);
  if (ix < 0 || iy < 0 || ix >= nx || iy >= ny) return false;
  return water.empty() || water[size_t(iy) * size_t(nx) + size_t(ix)] != 0;
}

Real Terrain::min_height() const {
  return *std::min_element(height.begin(), height.end());
}

Real Terrain::max_height() const {
  return *std::max_element(height.begin(), height.end());
}

std::vector<Real> water_column(const Terrain& t, Real x, Real y, Real r, Real level) {
  Real ground = t.height_at(x, y);
  for (const Real dx : {-r, r})
    for (const Real dy : {-r, r}) ground = std::max(ground, t.height_at(x + dx, y + dy));
  std::vector<Real> heights;
  for (Real z = ground + r; z <= level; z += 2 * r) heights.push_back(z);
  return heights;
}

}  // namespace sph
