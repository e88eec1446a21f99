#pragma once
// Checks of a forecast config against its flow that catch input which is wrong but would run
// and look right (issue 51's third round): water temperatures in kelvin, a centreline off the
// reach, and forecasts that could not finish (steps, the drift's sub-steps) or fit in memory
// (elements and their snapshots, bank bins). Each throws ConfigError naming the file and key.

#include <string>

#include "farfield/flows/reach_flow.h"
#include "farfield/forecast_config.h"
#include "farfield/model/centreline.h"
#include "reach/hydrograph.h"

namespace farfield {

// River water lies between these (degrees Celsius).
constexpr double kColdestWaterC = -2, kWarmestWaterC = 40;

// Refuses a temperature series outside river water's range, hinting at kelvin when a value
// reads as one.
void check_water_temperature(const reach::Hydrograph& celsius, const std::string& file,
                             const std::string& pointer);

// Refuses a centreline with a point outside the reach's grid (its pointer named) or of which
// less than half lies on the reach's water at the start: the leading edge and the banks are
// measured along it.
void check_centreline_on_water(const Centreline& line, const ForecastConfig& config,
                               const ReachFlow& flow, const std::string& file);

// Bytes one element takes in the model, and in each output's snapshot (the NetCDF's variables):
// floors, from the structures' sizes.
constexpr double kBytesPerElement = 300, kBytesPerElementOutput = 52;

// The forecast's work and memory before any of it is done: time steps times the drift's
// sub-steps (from the fastest flow at the start and the strongest wind) within max_steps; the
// elements (each release's) and their snapshots at every output, and the bank bins, within
// `memory_bytes`. `peak_wind` is the wind series' largest value (m/s).
void check_forecast_size(const ForecastConfig& config, const ReachFlow& flow,
                         const Centreline& line, double peak_wind, double memory_bytes,
                         const std::string& file);

}  // namespace farfield
