#include "reach/raster.h"

#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

namespace reach {

namespace {

// GDAL's drivers are registered once per process; GDALAllRegister is idempotent and
// thread-safe, so each entry point calls it rather than relying on a global initialiser.
void register_drivers() {
  GDALAllRegister();
}

struct DatasetCloser {
  void operator()(GDALDataset* d) const { GDALClose(d); }
};
using DatasetHandle = std::unique_ptr<GDALDataset, DatasetCloser>;

}  // namespace

namespace {

// The open dataset and its grid (its georeferencing checked); values not read.
struct OpenRaster {
  DatasetHandle dataset;
  Raster header;  // grid and CRS, no values
  bool north_up = true;
};

OpenRaster open_raster(const std::string& path) {
  register_drivers();
  CPLPushErrorHandler(CPLQuietErrorHandler);
  OpenRaster o;
  o.dataset.reset(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
  CPLPopErrorHandler();
  GDALDataset* d = o.dataset.get();
  if (!d) {
    const std::string why = CPLGetLastErrorMsg();
    throw RasterError(path + ": GDAL cannot open it as a raster" +
                      (why.empty() ? std::string() : " (" + why + ")"));
  }
  if (d->GetRasterCount() < 1) throw RasterError(path + ": the file holds no raster band");
  double gt[6];
  if (d->GetGeoTransform(gt) != CE_None)
    throw RasterError(path + ": no geotransform (the raster is not georeferenced)");
  if (gt[2] != 0 || gt[4] != 0)
    throw RasterError(path + ": a rotated or sheared raster (geotransform terms " +
                      std::to_string(gt[2]) + ", " + std::to_string(gt[4]) +
                      ") is not supported; warp it to north-up first (gdalwarp)");
  if (!(gt[1] > 0) || gt[5] == 0)
    throw RasterError(path + ": pixel size " + std::to_string(gt[1]) + " x " +
                      std::to_string(gt[5]) + " is not usable");
  Raster& r = o.header;
  r.grid.nx = d->GetRasterXSize();
  r.grid.ny = d->GetRasterYSize();
  r.grid.dx = gt[1];
  r.grid.dy = std::abs(gt[5]);
  r.grid.x0 = gt[0];
  o.north_up = gt[5] < 0;
  r.grid.y0 = o.north_up ? gt[3] + gt[5] * r.grid.ny : gt[3];
  const char* wkt = d->GetProjectionRef();
  r.crs_wkt = wkt ? wkt : "";
  return o;
}

}  // namespace

Raster raster_header(const std::string& path) {
  return open_raster(path).header;
}

CellBlock cells_within(const Grid& g, double x_min, double y_min, double x_max, double y_max) {
  CellBlock b;
  b.i0 = std::max(0, int(std::ceil((x_min - g.x0) / g.dx - 0.5)));
  b.i1 = std::min(g.nx - 1, int(std::floor((x_max - g.x0) / g.dx - 0.5)));
  b.j0 = std::max(0, int(std::ceil((y_min - g.y0) / g.dy - 0.5)));
  b.j1 = std::min(g.ny - 1, int(std::floor((y_max - g.y0) / g.dy - 0.5)));
  return b;
}

Raster read_raster(const std::string& path, const RasterRead& how) {
  if (how.coarsen < 1) throw std::invalid_argument("a coarsening factor must be >= 1");
  OpenRaster o = open_raster(path);
  const Grid whole = o.header.grid;
  CellBlock block{0, whole.nx - 1, 0, whole.ny - 1};
  const auto& w = how.window;
  if (!w.empty()) {
    block = cells_within(whole, w[0], w[1], w[2], w[3]);
    if (block.empty())
      return crop(o.header, w[0], w[1], w[2], w[3], "the window");  // throws, naming the extent
  }
  // The block at full resolution, then its blocks of `coarsen` cells a side averaged over their
  // valid cells, as coarsen() does (in its order, so the sums are the same), one strip of rows
  // at a time: only a strip of the fine raster is held.
  const int f = how.coarsen;
  Grid fine = whole;
  fine.nx = block.i1 - block.i0 + 1;
  fine.ny = block.j1 - block.j0 + 1;
  fine.x0 = whole.x0 + block.i0 * whole.dx;
  fine.y0 = whole.y0 + block.j0 * whole.dy;
  Raster r = o.header;
  r.grid = fine;
  r.grid.nx = (fine.nx + f - 1) / f;
  r.grid.ny = (fine.ny + f - 1) / f;
  r.grid.dx = fine.dx * f;
  r.grid.dy = fine.dy * f;
  r.values.assign(r.grid.cells(), std::nan(""));
  GDALRasterBand* band = o.dataset->GetRasterBand(1);
  int has_nodata = 0;
  const double nodata = band->GetNoDataValue(&has_nodata);
  std::vector<double> rows, strip;  // the strip's rows as the file holds them; in grid order
  size_t valid = 0;
  for (int J = 0; J < r.grid.ny; ++J) {
    const int j_first = J * f, rows_in = std::min(fine.ny, (J + 1) * f) - j_first;
    // The file's rows run north to south when north-up: the strip's first is its northernmost.
    const int first_row =
        o.north_up ? whole.ny - 1 - (block.j0 + j_first + rows_in - 1) : block.j0 + j_first;
    rows.resize(size_t(rows_in) * size_t(fine.nx));
    if (band->RasterIO(GF_Read, block.i0, first_row, fine.nx, rows_in, rows.data(), fine.nx,
                       rows_in, GDT_Float64, 0, 0) != CE_None)
      throw RasterError(path + ": reading band 1 failed (" + CPLGetLastErrorMsg() + ")");
    strip.resize(rows.size());
    for (int row = 0; row < rows_in; ++row) {
      const int j = o.north_up ? rows_in - 1 - row : row;
      for (int i = 0; i < fine.nx; ++i) {
        double v = rows[size_t(row) * size_t(fine.nx) + size_t(i)];
        if ((has_nodata && (v == nodata || (std::isnan(nodata) && std::isnan(v)))) ||
            !std::isfinite(v))
          v = std::nan("");
        else
          ++valid;
        strip[size_t(j) * size_t(fine.nx) + size_t(i)] = v;
      }
    }
    for (int I = 0; I < r.grid.nx; ++I) {
      double sum = 0;
      int count = 0;
      for (int j = 0; j < rows_in; ++j)
        for (int i = I * f; i < std::min(fine.nx, (I + 1) * f); ++i) {
          const double v = strip[size_t(j) * size_t(fine.nx) + size_t(i)];
          if (!std::isnan(v)) sum += v, ++count;
        }
      if (count > 0) r.values[r.grid.at(I, J)] = f == 1 ? sum : sum / count;
    }
  }
  if (valid == 0 && !how.allow_all_nodata)
    throw RasterError(path + ": every cell" + (w.empty() ? "" : " in the window") + " is nodata");
  return r;
}

void write_geotiff(const std::string& path, const Raster& r) {
  write_geotiff_bands(path, r.grid, r.crs_wkt, {r.values}, {""});
}

void write_geotiff_bands(const std::string& path, const Grid& grid, const std::string& crs_wkt,
                         const std::vector<Field>& bands,
                         const std::vector<std::string>& descriptions) {
  register_drivers();
  constexpr double kNoData = -9999.0;
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GTiff");
  if (!driver) throw std::runtime_error(path + ": GDAL has no GeoTIFF driver");
  char** options = nullptr;
  options = CSLSetNameValue(options, "COMPRESS", "DEFLATE");
  options = CSLSetNameValue(options, "PREDICTOR", "3");  // floating-point predictor
  DatasetHandle d(
      driver->Create(path.c_str(), grid.nx, grid.ny, int(bands.size()), GDT_Float32, options));
  CSLDestroy(options);
  if (!d) throw std::runtime_error(path + ": GDAL cannot create it (" + CPLGetLastErrorMsg() + ")");
  double gt[6] = {grid.x0, grid.dx, 0, grid.y0 + grid.dy * grid.ny, 0, -grid.dy};
  d->SetGeoTransform(gt);
  if (!crs_wkt.empty()) d->SetProjection(crs_wkt.c_str());
  std::vector<float> rows(grid.cells());
  for (size_t k = 0; k < bands.size(); ++k) {
    for (int row = 0; row < grid.ny; ++row) {
      const int j = grid.ny - 1 - row;
      for (int i = 0; i < grid.nx; ++i) {
        const double v = bands[k][grid.at(i, j)];
        rows[size_t(row) * size_t(grid.nx) + size_t(i)] = std::isnan(v) ? float(kNoData) : float(v);
      }
    }
    GDALRasterBand* band = d->GetRasterBand(int(k) + 1);
    band->SetNoDataValue(kNoData);
    if (k < descriptions.size() && !descriptions[k].empty())
      band->SetDescription(descriptions[k].c_str());
    if (band->RasterIO(GF_Write, 0, 0, grid.nx, grid.ny, rows.data(), grid.nx, grid.ny, GDT_Float32,
                       0, 0) != CE_None)
      throw std::runtime_error(path + ": writing failed (" + CPLGetLastErrorMsg() + ")");
  }
  d.reset();  // GDALClose flushes; an error there is GDAL's last message
  if (CPLGetLastErrorType() == CE_Failure)
    throw std::runtime_error(path + ": closing failed (" + CPLGetLastErrorMsg() + ")");
}

Raster crop(const Raster& r, double x_min, double y_min, double x_max, double y_max,
            const std::string& what) {
  const CellBlock b = cells_within(r.grid, x_min, y_min, x_max, y_max);
  const int i0 = b.i0, i1 = b.i1, j0 = b.j0, j1 = b.j1;
  if (b.empty())
    throw RasterError(what + ": no cell of the raster lies inside it (the raster spans x " +
                      std::to_string(r.grid.x0) + " to " +
                      std::to_string(r.grid.x0 + r.grid.nx * r.grid.dx) + ", y " +
                      std::to_string(r.grid.y0) + " to " +
                      std::to_string(r.grid.y0 + r.grid.ny * r.grid.dy) + ")");
  Raster c;
  c.crs_wkt = r.crs_wkt;
  c.grid = r.grid;
  c.grid.nx = i1 - i0 + 1;
  c.grid.ny = j1 - j0 + 1;
  c.grid.x0 = r.grid.x0 + i0 * r.grid.dx;
  c.grid.y0 = r.grid.y0 + j0 * r.grid.dy;
  c.values.resize(c.grid.cells());
  for (int j = 0; j < c.grid.ny; ++j)
    for (int i = 0; i < c.grid.nx; ++i)
      c.values[c.grid.at(i, j)] = r.values[r.grid.at(i0 + i, j0 + j)];
  return c;
}

std::string crs_wkt_of(const std::string& user) {
  OGRSpatialReference srs;
  CPLPushErrorHandler(CPLQuietErrorHandler);
  const OGRErr err = srs.SetFromUserInput(user.c_str());
  CPLPopErrorHandler();
  if (err != OGRERR_NONE) throw RasterError("unknown coordinate reference system \"" + user + "\"");
  char* wkt = nullptr;
  srs.exportToWkt(&wkt);
  std::string out = wkt ? wkt : "";
  CPLFree(wkt);
  return out;
}

bool crs_is_geographic(const std::string& wkt) {
  OGRSpatialReference srs;
  if (srs.importFromWkt(wkt.c_str()) != OGRERR_NONE) return false;
  return srs.IsGeographic() != 0;
}

LinearUnit crs_linear_unit(const std::string& wkt) {
  OGRSpatialReference srs;
  if (srs.importFromWkt(wkt.c_str()) != OGRERR_NONE) return {};
  const char* name = nullptr;
  const double metres = srs.GetLinearUnits(&name);
  return {name ? name : "", metres};
}

Raster coarsen(const Raster& r, int factor) {
  if (factor < 1) throw std::invalid_argument("a coarsening factor must be >= 1");
  Raster c;
  c.crs_wkt = r.crs_wkt;
  c.grid = r.grid;
  c.grid.nx = (r.grid.nx + factor - 1) / factor;
  c.grid.ny = (r.grid.ny + factor - 1) / factor;
  c.grid.dx = r.grid.dx * factor;
  c.grid.dy = r.grid.dy * factor;
  c.values.assign(c.grid.cells(), std::nan(""));
  for (int J = 0; J < c.grid.ny; ++J)
    for (int I = 0; I < c.grid.nx; ++I) {
      double sum = 0;
      int count = 0;
      for (int j = J * factor; j < std::min(r.grid.ny, (J + 1) * factor); ++j)
        for (int i = I * factor; i < std::min(r.grid.nx, (I + 1) * factor); ++i) {
          const double v = r.values[r.grid.at(i, j)];
          if (!std::isnan(v)) sum += v, ++count;
        }
      if (count > 0) c.values[c.grid.at(I, J)] = sum / count;
    }
  return c;
}

}  // namespace reach
