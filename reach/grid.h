#pragma once
// The regular grid of a reach: nx x ny square-or-rectangular cells, cell (i, j) centred at
// (x0 + (i + 1/2) dx, y0 + (j + 1/2) dy), j growing northwards (+y). Fields on it are flat
// vectors in row-major order, index j * nx + i.

#include <cstddef>
#include <vector>

namespace reach {

struct Grid {
  int nx = 0, ny = 0;
  double dx = 1, dy = 1;  // m
  double x0 = 0, y0 = 0;  // m: the south-west corner of cell (0, 0)

  size_t cells() const { return size_t(nx) * size_t(ny); }
  size_t at(int i, int j) const { return size_t(j) * size_t(nx) + size_t(i); }
  double x(int i) const { return x0 + (i + 0.5) * dx; }
  double y(int j) const { return y0 + (j + 0.5) * dy; }
  double cell_area() const { return dx * dy; }
};

using Field = std::vector<double>;

}  // namespace reach
