#pragma once
// A reach run from its config: the terrain raster (windowed, coarsened, a channel carved), the
// boundaries placed by map coordinates, the flow advanced to the end (or to a steady state), and
// the run folder written: rasters of depth, water level and velocity at each output time and the
// event's maxima as GeoTIFFs in the terrain's CRS, a map picture per output time, and reach.json
// (discharge through each section, volume balance, wetted area, the steady-state residual).

#include <atomic>
#include <memory>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "reach/raster.h"
#include "reach/reach_config.h"
#include "reach/shallow_water.h"

namespace reach {

// The solver of a config, on its terrain, with its boundaries and initial water, and what a run
// needs to write georeferenced output.
struct ReachModel {
  std::unique_ptr<ShallowWaterSolver> solver;
  Raster terrain;  // the grid the solver runs on, its bed (after carving) and CRS
  long carved_cells = 0;
  // The fastest wave the inputs promise (m/s): the critical flow of each inflow's peak over its
  // width, the initial water and a stage at rest. The run's step estimate starts from it, and
  // `wave_speed_key` names the input it comes from.
  double wave_speed = 0;
  std::string wave_speed_key;
  // 1 for the cells of the grid's edge that the sections take (water against the rest of the
  // edge stands against a wall).
  std::vector<char> section_cells;
};

// Throws ConfigError (naming `config_file` and the key, and the raster when it is at fault) for
// input that does not fit: a raster GDAL cannot open, no or a geographic CRS or one not in
// metres, elevations not finite or beyond Earth's, a window or a section outside the raster, a
// section with no open cell, two sections sharing cells, a Manning raster of another grid or
// with values out of range, a series (a hydrograph, a stage) that does not cover the run.

ReachModel build_reach(const ReachConfig& config, const std::string& config_file);

struct ReachRunOptions {
  std::string config_file;
  std::vector<std::string> overrides;
  std::string out_dir;
  bool force = false;
  const std::atomic<bool>* stop = nullptr;  // set by Ctrl-C: nothing is written, exit 130
  std::ostream* log = nullptr;              // progress and warnings
  bool terminal = false;
  int threads = 1;
};

// The name of the frame at time t among frames every `interval` seconds: whole seconds when the
// interval allows, more decimals otherwise, and more still until it differs from `previous`'s
// (a last frame or a steady stop close after an output), so no two frames share a file.
std::string frame_stamp(double t, double previous, double interval);

// Runs and writes the folder (whole or not at all); returns reach.json's content.
nlohmann::json run_reach(const ReachRunOptions& options);

}  // namespace reach
