#pragma once
// What a reach run writes, handed each step and each output time by run_reach as the SPH's
// frames are handed to sph/io/run_recorder: the rasters and map of each output, the event's
// maxima, the steady-state residual, and at the end bed.tif, the maxima's rasters, map.png and
// reach.json's content (reach/run_folder.h reads them back).

#include <filesystem>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "reach/raster.h"
#include "reach/reach_config.h"
#include "reach/reach_run.h"

namespace reach {

class ReachRecorder {
 public:
  // Writes into `dir` (the output folder's staging); warnings go to `log`.
  ReachRecorder(const ReachModel& model, const ReachConfig& config, std::filesystem::path dir,
                std::ostream& log);

  // After each step: the maxima, and every steady_window the residual (how fast the depths
  // drift) and whether the flow is steady.
  void after_step();
  bool steady() const { return steady_; }
  double residual() const { return residual_; }

  // An output time: the depth, level and velocity rasters, the map, and its row of reach.json.
  void write_frame();

  // bed.tif, max_depth.tif, max_level.tif and map.png written; returns reach.json's content.
  nlohmann::json finish(long steps, int threads, double wall_s);

 private:
  Raster raster_of(const Field& values) const;
  bool balanced() const;

  const ReachModel& model_;
  const ShallowWaterSolver& solver_;
  const ReachConfig& config_;
  std::filesystem::path dir_;
  std::ostream& log_;
  long open_cells_ = 0;
  double volume0_ = 0;
  Field max_depth_, max_level_;
  nlohmann::json frames_ = nlohmann::json::array();
  std::vector<std::string> warnings_;
  double depth_scale_ = 0, speed_scale_ = 0;
  double last_frame_time_ = -1;  // no frame yet
  // The steady-state residual: the depths at the start of its window, and the window's start.
  Field window_depth_;
  double window_start_ = 0, residual_;
  bool steady_ = false;
};

}  // namespace reach
