#pragma once
// A finished reach run's folder (`spill-sim reach --out DIR`, reach/reach_run.h) as its readers
// see it: reach.json's output times and steady state, bed.tif, and each output's depth and
// discharge per width. The far field's flow (farfield/flows/reach_flow.h) and a near field's window
// (reach/near_field_window.h) read the folder through here, so its keys and its files are read
// one way.

#include <nlohmann/json.hpp>
#include <string>

#include "reach/grid.h"
#include "reach/raster.h"

namespace reach {

// One output time: depth (NaN where closed) and discharge per width h u, h v (0 where dry, NaN
// where closed), so that values interpolate smoothly up to a shore.
struct ReachOutput {
  double t_s = 0;
  Field depth, qx, qy;
};

class ReachRunFolder {
 public:
  // Throws common::ConfigError naming `config_file` and `folder_pointer` (the key that named
  // the folder) when `dir` holds no reach.json or bed.tif (a run before bed.tif was written, or
  // not a reach run) or reach.json lists no output.
  ReachRunFolder(const std::string& dir, const std::string& config_file,
                 const std::string& folder_pointer);

  const std::string& dir() const { return dir_; }
  const nlohmann::json& summary() const { return summary_; }
  size_t outputs() const { return summary_.at("frames").size(); }
  double time(size_t output) const;
  // Whether the run stopped at a steady state (its last output then holds for ever after).
  bool steady() const;
  // The output nearest `t` within half a second (outputs may be closer than that); throws
  // ConfigError naming `time_pointer` and listing the outputs when none is.
  size_t output_at(double t, const std::string& time_pointer) const;
  // bed.tif: the bed the flow ran on (coarsened, carved), NaN where closed, with the CRS.
  const Raster& bed() const { return bed_; }
  // An output's rasters; throws ConfigError naming the folder's key for one off bed.tif's grid.
  ReachOutput read(size_t output) const;

 private:
  std::string dir_, config_file_, folder_pointer_;
  nlohmann::json summary_;
  Raster bed_;
};

}  // namespace reach
