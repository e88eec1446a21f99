#pragma once
// Georeferenced rasters through GDAL: elevation in (GeoTIFF, ESRI ASCII and every other format
// GDAL reads), depth, velocity and level out (GeoTIFF). A raster keeps its georeferencing: GDAL's
// geotransform puts the upper-left corner of the first pixel at (GT[0], GT[3]) with pixels GT[1]
// wide and GT[5] high (negative for north-up); here it becomes a Grid whose cell (0, 0) is the
// south-west one, rows running north, so that the solver's y grows northwards like the map's.
// The coordinate reference system is carried as WKT; nodata becomes NaN.

#include <string>
#include <vector>

#include "common/exit_codes.h"
#include "reach/grid.h"

namespace reach {

// A raster that cannot be used as given (exit code 2); the message names the file.
class RasterError : public common::InputError {
 public:
  using common::InputError::InputError;
};

struct Raster {
  Grid grid;            // x0, y0: the south-west corner in the CRS's units; dx, dy > 0
  Field values;         // grid order (row 0 the southernmost); NaN where the file has nodata
  std::string crs_wkt;  // empty when the file has none
};

// How much of a raster to read: the cells whose centres lie in `window` ([x_min, y_min, x_max,
// y_max] in map coordinates, what crop() keeps; empty: all), averaged in blocks of `coarsen`
// cells a side as coarsen() does; `allow_all_nodata` for a velocity raster of a dry reach.
struct RasterRead {
  std::vector<double> window;
  int coarsen = 1;
  bool allow_all_nodata = false;
};

// Band 1 of `path`, as `how` says, read from the file a strip of rows at a time (a 20,000 x
// 20,000 raster was read whole, 7 GB, before its window and coarsening applied): the same
// values as crop() and coarsen() of the whole. Refuses (RasterError naming the file) a file GDAL
// cannot open, a rotated or sheared geotransform, a window with no cell, and (unless
// allow_all_nodata) a raster or window with no valid cell.
Raster read_raster(const std::string& path, const RasterRead& how = {});

// The raster's grid and CRS without reading its values (to size what reading it would take).
Raster raster_header(const std::string& path);

// The cells of a grid whose centres lie in [x_min, x_max] x [y_min, y_max].
struct CellBlock {
  int i0 = 0, i1 = -1, j0 = 0, j1 = -1;
  bool empty() const { return i1 < i0 || j1 < j0; }
  double cells() const { return empty() ? 0.0 : double(i1 - i0 + 1) * double(j1 - j0 + 1); }
};
CellBlock cells_within(const Grid& grid, double x_min, double y_min, double x_max, double y_max);

// Writes `raster` as a single-band Float32 GeoTIFF (DEFLATE) with nodata -9999 where a value is
// NaN, its geotransform and CRS. Throws std::runtime_error naming the file when GDAL fails.
void write_geotiff(const std::string& path, const Raster& raster);
// The same with one band per field of `bands` (each on `grid`), band k described by
// `descriptions[k]` (GDAL's band description, which gdalinfo prints).
void write_geotiff_bands(const std::string& path, const Grid& grid, const std::string& crs_wkt,
                         const std::vector<Field>& bands,
                         const std::vector<std::string>& descriptions);

// The cells of `r` whose centres lie in [x_min, x_max] x [y_min, y_max] (map coordinates);
// throws RasterError naming `what` when none does.
Raster crop(const Raster& raster, double x_min, double y_min, double x_max, double y_max,
            const std::string& what);

// `user` (EPSG:2193, a WKT, a PROJ string: whatever GDAL's SetFromUserInput takes) as WKT;
// throws RasterError naming it when GDAL does not know it.
std::string crs_wkt_of(const std::string& user);
// Whether the CRS is geographic (degrees), which a grid in metres cannot use.
bool crs_is_geographic(const std::string& wkt);
// The horizontal unit of a projected CRS: its name and its length in metres (1 for the metre;
// 0.3048006 for the US survey foot). {"", 0} when the WKT does not read.
struct LinearUnit {
  std::string name;
  double metres = 0;
};
LinearUnit crs_linear_unit(const std::string& wkt);

// The mean of each factor x factor block of valid cells (NaN where a block has none); the last
// row and column of blocks may be partial. For running a fine DEM on a coarser grid.
Raster coarsen(const Raster& raster, int factor);

}  // namespace reach
