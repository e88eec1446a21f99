#pragma once
// Values of a cell-centred field between the cells' centres.

#include "reach/grid.h"

namespace reach {

// Bilinear between the centres of the valid (finite) cells around (x, y), their weights
// renormalised, so that a closed or nodata cell gives no weight; NaN when none of the four is
// valid. Points beyond the outer centres take the edge cells' values.
double bilinear_valid(const Field& values, const Grid& grid, double x, double y);

}  // namespace reach
