#pragma once
// What a forecast keeps at each output time and the files it makes of them at the end (the
// files forecast_run.h lists), as sph/io/run_recorder does for a scene: the step loop hands
// the model over at each output time, and finish() writes the folder's files.

#include <atomic>
#include <chrono>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "farfield/flows/reach_flow.h"
#include "farfield/forecast_setup.h"
#include "farfield/outputs/geojson_output.h"
#include "farfield/outputs/lon_lat.h"
#include "farfield/outputs/netcdf_output.h"

namespace farfield {

// What the run knows and the recorder does not: forecast.json's run figures.
struct ForecastRunFacts {
  std::string config_file;
  double worst_closure = 0;  // the budget's worst relative closure error over the steps
  size_t handover_parcels = 0;
  double handed_over_m3 = 0;
  nlohmann::json handover_summary;  // the near field's run, null without one
  std::chrono::steady_clock::time_point wall_start;
  int threads = 1;
  nlohmann::json ensemble;                              // forecast.json's "ensemble", null without
  const ShoreProbability* shore_probability = nullptr;  // the ensemble's, for shoreline.geojson
};

class ForecastRecorder {
 public:
  // `dir` is the staging folder; `stop` (may be null) is checked between files, so that a
  // Ctrl-C while writing throws common::Interrupted.
  ForecastRecorder(std::filesystem::path dir, const ForecastSetup& setup, const ReachFlow& flow,
                   bool pictures, const std::atomic<bool>* stop);

  // One output time: its forecast.json record, slick, shore and elements, and its map.
  void record(const FarFieldModel& model, const std::vector<WatchPoint>& points);

  // Writes budget.csv/svg, the GeoJSON, elements.nc and forecast.json; returns the latter.
  nlohmann::json finish(const FarFieldModel& model, const std::vector<WatchPoint>& points,
                        const ForecastRunFacts& facts);

  // The output times so far (s) and their UTC clocks.
  std::vector<double> output_times() const;
  std::vector<std::string> output_clocks() const;

 private:
  void check_stop() const;
  std::string clock(double t_s) const;
  nlohmann::json summary(const FarFieldModel& model, const std::vector<WatchPoint>& points,
                         const ForecastRunFacts& facts) const;

  std::filesystem::path dir_;
  const ForecastSetup& setup_;
  const ReachFlow& flow_;
  bool pictures_;
  const std::atomic<bool>* stop_;
  LonLat lon_lat_;
  double depth_scale_ = 0.5, speed_scale_ = 0.5;  // the maps' fixed colour scales
  nlohmann::json outputs_ = nlohmann::json::array();
  std::vector<SlickSnapshot> slicks_;
  std::vector<ShoreSnapshot> shores_;
  std::vector<ElementSnapshot> elements_;
};

}  // namespace farfield
