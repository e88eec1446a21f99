#pragma once
// Terrain from files: ESRI ASCII grids (.asc) and grayscale PNG height maps (8 or 16 bit), with
// an optional PNG water mask. Both formats store the northernmost row first; Terrain stores the
// southernmost first, so rows are flipped on reading and writing. Every error names the file and
// where in it (header key, or row and column): a missing file, a malformed header, a cell that is
// NODATA, NaN or not a number, a mask of another size.

#include <string>

#include "sph/river/terrain.h"

namespace sph {

// Header keys ncols, nrows, xllcorner or xllcenter, yllcorner or yllcenter, cellsize and the
// optional NODATA_value, then nrows rows of ncols heights.
Terrain read_esri_ascii(const std::string& path);
void write_esri_ascii(const std::string& path, const Terrain& terrain);

// Gray value v of a pixel (0 .. 2^bits - 1) becomes the height z_min + (z_max - z_min) v / max;
// pixel centres are cell_size apart, the south-west (bottom-left) one at (origin_x, origin_y).
Terrain read_height_png(const std::string& path, Real origin_x, Real origin_y, Real cell_size,
                        Real z_min, Real z_max);
// 16-bit gray, heights mapped linearly from [z_min, z_max]; for exporting generated terrain.
void write_height_png(const std::string& path, const Terrain& terrain, Real z_min, Real z_max);

// Sets terrain.water from a PNG of the terrain's size: nonzero gray (or alpha-less colour) is
// water.
void read_water_mask_png(const std::string& path, Terrain& terrain);

}  // namespace sph
