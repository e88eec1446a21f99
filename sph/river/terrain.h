#pragma once
// Terrain as a regular grid of heights over the x-y plane, with an optional water mask: the river
// bed and banks of a river scene. It comes from a height map (sph/river/height_map_io.h) or from
// the built-in river generator (sph/river/river_generator.h) and is sampled into boundary particles
// like any height field.

#include <cstdint>
#include <vector>

#include "sph/core/types.h"

namespace sph {

struct Terrain {
  Real origin_x = 0, origin_y = 0;  // centre of cell (0, 0), the south-west corner
  Real cell_size = 1;
  int nx = 0, ny = 0;               // cells along x (east) and y (north)
  std::vector<Real> height;         // [ny * nx], row iy = ny - 1 is the northernmost
  std::vector<std::uint8_t> water;  // [ny * nx] 1 where the river is; empty: no mask

  Real& at(int ix, int iy) { return height[size_t(iy) * size_t(nx) + size_t(ix)]; }
  Real at(int ix, int iy) const { return height[size_t(iy) * size_t(nx) + size_t(ix)]; }
  Real max_x() const { return origin_x + cell_size * Real(nx - 1); }
  Real max_y() const { return origin_y + cell_size * Real(ny - 1); }
  // Bilinear height at (x, y), clamped to the grid's edge beyond it.
  Real height_at(Real x, Real y) const;
  // The mask of the nearest cell (true everywhere without a mask; false outside the grid).
  bool is_water(Real x, Real y) const;
  Real min_height() const;
  Real max_height() const;
};

// Centre heights of a column of water particles of `radius` at (x, y), for filling a river and
// for its inflow layers: stacked from the highest ground under the particle's footprint (so the
// lowest one rests on the bed without overlapping it on a slope) up to the last one within half a
// spacing of `level`. Empty where the ground is too high.
std::vector<Real> water_column(const Terrain& terrain, Real x, Real y, Real radius, Real level);

}  // namespace sph
