// Rasters through GDAL (reach/raster.h): georeferencing and orientation from files written by
// hand, the shipped DEMs' documented facts, and refusals that name the file.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>

#include "reach/raster.h"

namespace fs = std::filesystem;

namespace {

fs::path temp_file(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("spill_raster_" + std::to_string(getpid()));
  fs::create_directories(dir);
  return dir / name;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const reach::RasterError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

// An ESRI ASCII grid written here: its first row is the northernmost, its corner the south-west
// one, and NODATA cells become NaN.
TEST(Raster, ReadsAnEsriAsciiGridNorthUpWithNodata) {
  const fs::path path = temp_file("grid.asc");
  std::ofstream(path) << "ncols 3\nnrows 2\nxllcorner 100\nyllcorner 200\ncellsize 5\n"
                         "NODATA_value -9999\n1 2 3\n4 -9999 6\n";
  const reach::Raster r = reach::read_raster(path.string());
  ASSERT_EQ(r.grid.nx, 3);
  ASSERT_EQ(r.grid.ny, 2);
  EXPECT_EQ(r.grid.dx, 5.0);
  EXPECT_EQ(r.grid.dy, 5.0);
  EXPECT_EQ(r.grid.x0, 100.0);
  EXPECT_EQ(r.grid.y0, 200.0);
  EXPECT_EQ(r.values[r.grid.at(0, 1)], 1.0);  // north-west
  EXPECT_EQ(r.values[r.grid.at(2, 1)], 3.0);
  EXPECT_EQ(r.values[r.grid.at(0, 0)], 4.0);  // south-west
  EXPECT_TRUE(std::isnan(r.values[r.grid.at(1, 0)]));
  EXPECT_EQ(r.values[r.grid.at(2, 0)], 6.0);
}

// A GeoTIFF written and read back keeps values, NaN, geotransform and CRS.
TEST(Raster, AGeoTiffRoundTripKeepsValuesAndGeoreferencing) {
  reach::Raster r;
  r.grid.nx = 4, r.grid.ny = 3, r.grid.dx = 2.5, r.grid.dy = 2.5, r.grid.x0 = 1771385.0,
  r.grid.y0 = 5472254.0;
  for (size_t c = 0; c < r.grid.cells(); ++c) r.values.push_back(0.25 * double(c));
  r.values[5] = std::nan("");
  const reach::Raster waikanae = reach::read_raster(
      std::string(SPILL_SOURCE_DIR) + "/terrain/waikanae_river_10m/waikanae_dem_10m.tif");
  r.crs_wkt = waikanae.crs_wkt;
  const fs::path path = temp_file("round.tif");
  reach::write_geotiff(path.string(), r);
  const reach::Raster back = reach::read_raster(path.string());
  EXPECT_EQ(back.grid.nx, 4);
  EXPECT_EQ(back.grid.ny, 3);
  EXPECT_EQ(back.grid.x0, r.grid.x0);
  EXPECT_EQ(back.grid.y0, r.grid.y0);
  EXPECT_EQ(back.grid.dx, 2.5);
  for (size_t c = 0; c < r.grid.cells(); ++c)
    if (c == 5)
      EXPECT_TRUE(std::isnan(back.values[c]));
    else
      EXPECT_EQ(back.values[c], r.values[c]) << c;
  EXPECT_NE(back.crs_wkt.find("2193"), std::string::npos);
}

// The shipped Waikanae DEM as its README describes it: 144 x 96 cells of 10 m, upper-left corner
// (1771385, 5473214), EPSG:2193, every cell valid, heights 3.203-40.974 m.
TEST(Raster, TheShippedWaikanaeDemIsAsDocumented) {
  const reach::Raster r = reach::read_raster(std::string(SPILL_SOURCE_DIR) +
                                             "/terrain/waikanae_river_10m/waikanae_dem_10m.tif");
  EXPECT_EQ(r.grid.nx, 144);
  EXPECT_EQ(r.grid.ny, 96);
  EXPECT_EQ(r.grid.dx, 10.0);
  EXPECT_EQ(r.grid.x0, 1771385.0);
  EXPECT_EQ(r.grid.y0 + r.grid.ny * r.grid.dy, 5473214.0);
  EXPECT_NE(r.crs_wkt.find("NZGD2000"), std::string::npos);
  double lo = 1e9, hi = -1e9;
  for (double v : r.values) {
    ASSERT_FALSE(std::isnan(v));
    lo = std::min(lo, v), hi = std::max(hi, v);
  }
  EXPECT_NEAR(lo, 3.203, 5e-4);
  EXPECT_NEAR(hi, 40.974, 5e-4);
}

// Coarsening averages the valid cells of each block.
TEST(Raster, CoarseningAveragesTheValidCellsOfEachBlock) {
  reach::Raster r;
  r.grid.nx = 4, r.grid.ny = 2, r.grid.dx = r.grid.dy = 1;
  r.values = {1, 3, 5, std::nan(""), 2, 4, 7, std::nan("")};
  const reach::Raster c = reach::coarsen(r, 2);
  ASSERT_EQ(c.grid.nx, 2);
  ASSERT_EQ(c.grid.ny, 1);
  EXPECT_EQ(c.grid.dx, 2.0);
  EXPECT_DOUBLE_EQ(c.values[0], 2.5);
  EXPECT_DOUBLE_EQ(c.values[1], 6.0);
}

TEST(Raster, RefusesWhatItCannotUseNamingTheFile) {
  EXPECT_NE(
      error_of([] { reach::read_raster("/nonexistent/dem.tif"); }).find("/nonexistent/dem.tif"),
      std::string::npos);
  const fs::path text = temp_file("notes.tif");
  std::ofstream(text) << "not a raster\n";
  EXPECT_NE(error_of([&] { reach::read_raster(text.string()); }).find("cannot open"),
            std::string::npos);
  const fs::path empty = temp_file("empty.asc");
  std::ofstream(empty) << "ncols 2\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize 1\n"
                          "NODATA_value -9999\n-9999 -9999\n";
  EXPECT_NE(error_of([&] { reach::read_raster(empty.string()); }).find("every cell is nodata"),
            std::string::npos);
}

// A window read from the file holds exactly the cells that reading it whole and cropping kept,
// and coarsened while read the values coarsening the crop gives, without reading the rest (a 20,000
// x 20,000 raster was read whole, 7 GB, before the window applied).
TEST(Raster, AWindowReadFromTheFileIsTheWholeRasterCropped) {
  reach::Raster r;
  r.grid.nx = 37, r.grid.ny = 23, r.grid.dx = 2, r.grid.dy = 3;
  r.grid.x0 = 1000, r.grid.y0 = 5000;
  for (int j = 0; j < r.grid.ny; ++j)
    for (int i = 0; i < r.grid.nx; ++i) r.values.push_back(i == 5 && j == 7 ? NAN : i + 100 * j);
  r.crs_wkt = reach::crs_wkt_of("EPSG:2193");
  const fs::path path = temp_file("window.tif");
  reach::write_geotiff(path.string(), r);
  const reach::Raster whole = reach::read_raster(path.string());
  for (const std::vector<double>& w : std::vector<std::vector<double>>{
           {1010, 5020, 1030, 5040}, {990, 4990, 1005, 5100}, {1070, 5060, 2000, 6000}}) {
    const reach::Raster cropped = reach::crop(whole, w[0], w[1], w[2], w[3], "the window");
    const reach::Raster read = reach::read_raster(path.string(), {w});
    ASSERT_EQ(read.grid.nx, cropped.grid.nx);
    ASSERT_EQ(read.grid.ny, cropped.grid.ny);
    EXPECT_EQ(read.grid.x0, cropped.grid.x0);
    EXPECT_EQ(read.grid.y0, cropped.grid.y0);
    for (size_t k = 0; k < read.values.size(); ++k)
      if (std::isnan(cropped.values[k]))
        EXPECT_TRUE(std::isnan(read.values[k]));
      else
        EXPECT_EQ(read.values[k], cropped.values[k]) << k;
  }
  // Coarsened while read (strips of rows, partial blocks at the north and east edges) it is
  // coarsen() of the crop, to the bit.
  for (const int f : {2, 3, 5}) {
    const std::vector<double> w{1003, 5004, 1061, 5067};
    const reach::Raster expected =
        reach::coarsen(reach::crop(whole, w[0], w[1], w[2], w[3], "the window"), f);
    const reach::Raster read = reach::read_raster(path.string(), {w, f});
    ASSERT_EQ(read.grid.nx, expected.grid.nx);
    ASSERT_EQ(read.grid.ny, expected.grid.ny);
    EXPECT_EQ(read.grid.dx, expected.grid.dx);
    EXPECT_EQ(read.grid.x0, expected.grid.x0);
    EXPECT_EQ(read.grid.y0, expected.grid.y0);
    for (size_t k = 0; k < read.values.size(); ++k)
      if (std::isnan(expected.values[k]))
        EXPECT_TRUE(std::isnan(read.values[k]));
      else
        EXPECT_EQ(read.values[k], expected.values[k]) << f << " " << k;
  }
  EXPECT_NE(error_of([&] {
              reach::read_raster(path.string(), {{0, 0, 10, 10}});
            }).find("window"),
            std::string::npos);
}
