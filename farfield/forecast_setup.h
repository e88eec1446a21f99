#pragma once
// A forecast's model from its config, checked against its flow before anything runs: the oil
// from the library, the reach run's flow, the centreline and its banks, the weather, the
// releases and the watch points.

#include <ctime>
#include <string>
#include <vector>

#include "farfield/forecast_config.h"
#include "farfield/model/far_field_model.h"
#include "farfield/outputs/forecast_metrics.h"

namespace farfield {

struct ForecastSetup {
  ForecastConfig config;
  FarFieldSetup model;
  std::vector<WatchPoint> watch_points;
  std::time_t start_epoch = 0;           // config.start_date in seconds since 1970 (UTC)
  std::vector<OilRecord> ensemble_oils;  // config.ensemble's oils, loaded
};

// Throws ConfigError naming the file and key for an unknown oil, a negative rate, a release or
// watch point outside the reach, a series (wind, temperature, waves, rate) that does not cover
// the forecast, an unknown bank class, a forecast too long or too large for this machine.
ForecastSetup build_forecast(const ForecastConfig& config, const std::string& config_file);

}  // namespace farfield
