#pragma once
// A far-field forecast from its config (`spill-sim forecast --config FILE --out DIR`): the oil
// released where the config says (a point or a line, a rate over time) on a finished reach run's
// flow, stepped to the end, and the run folder written whole or not at all:
//   forecast.json      per output time: oiled area, leading edge (km), oiled length and stranded
//                      volume per bank and km, the budget, what reached each watch point
//   budget.csv, budget.svg   the budget over time
//   slick.geojson, shoreline.geojson   RFC 7946, WGS 84 lon/lat (geojson_output.h)
//   elements.nc        CF-1.6 trajectory NetCDF of the elements (netcdf_output.h)
//   png/map_NNNNN.png  a map per output time (forecast_map.h), in forecast.json's order
// and with an `/ensemble` section, its members' probabilities (forecast_ensemble.h):
//   probability.tif    per output time, the share of members that oiled each cell by then
//   png/probability.png  the last of those over the reach's map
// Its members can run as a job array's shards (`shard`), assembled by `members_from`.

#include <atomic>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "common/array_task.h"
#include "farfield/forecast_setup.h"
#include "farfield/forecast_steps.h"

namespace farfield {

struct ForecastRunOptions {
  std::string config_file;
  std::vector<std::string> overrides;
  std::string out_dir;
  bool force = false;
  bool pictures = true;
  // The near field's oil (sorted by time) and what forecast.json says of its run.
  std::vector<HandoverParcel> handover;
  nlohmann::json handover_summary;
  const std::atomic<bool>* stop = nullptr;  // set by Ctrl-C: nothing is written, exit 130
  std::ostream* log = nullptr;
  bool terminal = false;
  int threads = 1;
  // An ensemble over a job array: with `shard`, run only that shard's members and write their
  // tally to out_dir/ensemble_shard_I_of_N.json (nothing else); with `members_from`, run the
  // forecast and take the members from the shards' files in that folder instead of running them.
  std::optional<common::ArrayTask> shard;
  std::string members_from;
};

// Runs and writes the folder; returns forecast.json's content (a shard: what its file holds but
// the tally).
nlohmann::json run_forecast(const ForecastRunOptions& options);

}  // namespace farfield
