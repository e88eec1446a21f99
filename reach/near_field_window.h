#pragma once
// A near field's window on a finished reach run: a box at a leak site, turned so that its +x runs
// with the river, sampled from the run folder's rasters (bed.tif and one output time's depth and
// velocity) onto a fine local grid. This is how an SPH near field sits inside a real river: the
// scene's terrain, water and inflow come from here (sph/near_field/reach_terrain.h). Nothing of
// SPH is in this file; the window is plain arrays in the box's own frame.
//
// The box's frame: x from 0 (upstream end) to `length` along the bearing, y from -width/2 (right
// bank, looking downstream) to +width/2 (left bank), z the map's elevation. The rasters are
// cell-centred; values between cells are bilinear, over the valid cells only (a closed or nodata
// cell gives no weight). Velocities come from the discharge per width (depth x velocity, zero
// where dry) divided by the depth, so a dry cell next to a wet one does not drag the speed to 0.

#include <string>
#include <vector>

namespace reach {

struct NearFieldRequest {
  std::string run_dir;                // a folder written by `spill-sim reach`
  double time = -1;                   // output time to use (s); < 0: the run's last
  double centre_x = 0, centre_y = 0;  // map coordinates of the box's centre
  double length = 0, width = 0;       // m, along and across the flow
  double heading_deg = -1;            // compass bearing of the box's +x; < 0: the mean flow's
  double cell_size = 0;               // m, spacing of the local grid
  double min_depth = 0.01;            // m: shallower reach water counts as dry
  // For error messages: the file and JSON pointer of the settings (e.g. "scene.json",
  // "/terrain/reach").
  std::string config_file, pointer;
};

struct NearFieldWindow {
  int nx = 0, ny = 0;    // local grid points along x and y
  double cell_size = 0;  // point (i, j) at x = i cell_size, y = -width / 2 + j cell_size
  double width = 0;
  std::vector<double> bed;     // [j * nx + i] map elevation of the bed
  std::vector<double> depth;   // water depth (0 where dry)
  std::vector<double> along;   // depth-averaged velocity along +x of the box (0 where dry)
  std::vector<double> across;  // and along +y
  double heading_deg = 0;      // the bearing used
  double time_s = 0;           // the output time sampled
  std::string crs_wkt;
  double centre_x = 0, centre_y = 0, length = 0;

  size_t at(int i, int j) const { return size_t(j) * size_t(nx) + size_t(i); }
  double x(int i) const { return double(i) * cell_size; }
  double y(int j) const { return -0.5 * width + double(j) * cell_size; }
  // Map coordinates of the box's point (x, y).
  void to_map(double x, double y, double& east, double& north) const;
  // Over the points of the column nearest `x` with depth above `min_depth`: the mean water
  // level, and the velocity along +x weighted by depth (the section's discharge over its area).
  // Both NaN when the column is dry.
  double section_level(double x, double min_depth) const;
  double section_velocity(double x, double min_depth) const;
};

// Reads the run folder and samples the box. Throws common::ConfigError naming
// request.config_file and the key for: a folder without reach.json or bed.tif (the run predates
// them or is not a reach run), a time with no output, a box whose corners leave the reach's grid,
// a box with no water, no flow to take the heading from; reach::RasterError for a raster GDAL
// cannot read.
NearFieldWindow sample_near_field(const NearFieldRequest& request);

}  // namespace reach
