#pragma once
// Checks of a reach config against its terrain that catch input which is wrong but would run and
// look right (issue 51's third round): a CRS in feet, elevations that are nodata values GDAL was
// not told of, series that end before the run, sections sharing cells, and runs that could not
// end in a sensible number of steps. Each throws ConfigError naming the file and the key.

#include <string>
#include <utility>
#include <vector>

#include "reach/hydrograph.h"
#include "reach/raster.h"
#include "reach/reach_config.h"
#include "reach/reach_run.h"
#include "reach/shallow_water.h"

namespace reach {

// Elevations beyond these are not ground on Earth (the Challenger Deep, Everest).
constexpr double kLowestGround = -11000, kHighestGround = 9000;

// Refuses elevations beyond Earth's (a nodata value GDAL was not told of, 1e30 or -3.4e38,
// reads as ground otherwise; infinities and NaN read as nodata), naming the raster and a cell.
void check_elevations(const Raster& raster, const std::string& raster_file,
                      const std::string& config_file);

// Refuses a CRS whose unit is not the metre: the solver takes the cells' size as metres, so a
// grid in US survey feet would run with cells 3.3 times too large. `what` names the CRS's source.
void check_metres(const std::string& wkt, const std::string& config_file,
                  const std::string& pointer, const std::string& what);

// Refuses a series given as points or a file that does not hold values over 0 to `end_time`
// (the solver would hold its last value without a word); a constant always does.
void check_covers(const SeriesConfig& series, const Hydrograph& values, double end_time,
                  const std::string& config_file, const std::string& pointer);

// Refuses two sections on one side sharing cells (the water a cell lets in would also leave
// through it, and the volume balance would not close), naming the later one's key.
void check_sections_apart(const std::vector<std::pair<Section, std::string>>& placed,
                          const std::string& config_file);

// Bytes one cell of the solver's grid takes in a run: the solver's state, bed and roughness, a
// step's padded scratch arrays and face fluxes, and the run's maxima and frame fields (counted
// from the structures: a floor). Reading a raster holds 16 bytes per cell of a strip of
// `coarsen` rows and of the coarse grid.
constexpr double kBytesPerReachCell = 350, kBytesPerCellRead = 16;

// Refuses a terrain (the cells in its window, or all; the Manning raster's too) that cannot be
// read, or whose coarsened grid cannot be run, within `memory_bytes`, naming /terrain/window or
// /terrain/coarsen; and a window with no cell of the raster.
void check_terrain_size(const Raster& header, const TerrainConfig& terrain, double memory_bytes,
                        const std::string& config_file);

// The speed of the waves critical flow carries at discharge q per unit width (m/s).
double critical_wave_speed(double q);

// No river runs deeper than this at critical flow (the Amazon's 200,000 m^3/s over 5 km is
// 5.5 m): a discharge that would is not one the grid can carry.
constexpr double kDeepestCriticalFlow = 100;

// Refuses an inflow whose peak discharge over `width` would run deeper than
// kDeepestCriticalFlow at critical flow, naming `pointer` (a discharge of 4e9 m^3/s over 60 m
// ran at steps of 0.2 ms).
void check_carried(double peak, double width, const std::string& config_file,
                   const std::string& pointer);

// The number of steps `model` needs at least to reach the config's end time (its steps are at
// most max_dt and the CFL step of model.wave_speed). Throws ConfigError, naming the key that
// limits the step, when that exceeds max_steps, or when the frames exceed kMaxReachFrames.
constexpr double kMaxReachFrames = 100000;
double check_run_length(const ReachConfig& config, const ReachModel& model,
                        const std::string& config_file);

}  // namespace reach
