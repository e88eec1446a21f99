#include "farfield/forecast_checks.h"

#include <algorithm>
#include <cmath>

#include "common/config_error.h"
#include "common/number_text.h"

namespace farfield {

namespace {}  // namespace

void check_water_temperature(const reach::Hydrograph& celsius, const std::string& file,
                             const std::string& pointer) {
  for (const auto& [t, c] : celsius.points()) {
    if (c >= kColdestWaterC && c <= kWarmestWaterC) continue;
    const bool kelvin = c >= 273.15 + kColdestWaterC && c <= 273.15 + kWarmestWaterC;
    throw common::ConfigError(
        file, pointer,
        common::number_text(c) + " at " + common::number_text(t) +
            " s is not a river's water temperature in degrees " + "Celsius (" +
            common::number_text(kColdestWaterC) + " to " + common::number_text(kWarmestWaterC) +
            ")" +
            (kelvin ? ": it reads as kelvin, " + common::number_text(c) + " K is " +
                          common::number_text(c - 273.15) + " degrees Celsius"
                    : std::string()));
  }
}

void check_centreline_on_water(const Centreline& line, const ForecastConfig& c,
                               const ReachFlow& flow, const std::string& file) {
  const reach::Grid& g = flow.grid();
  for (size_t k = 0; k < c.centreline.size(); ++k) {
    const double x = c.centreline[k][0], y = c.centreline[k][1];
    if (flow.sample(x, y, 0).where == FlowWhere::outside)
      throw common::ConfigError(file, "/centreline/" + std::to_string(k),
                                "(" + common::number_text(x) + ", " + common::number_text(y) +
                                    ") lies outside the reach's grid (" +
                                    common::number_text(g.x0) + ", " + common::number_text(g.y0) +
                                    " to " + common::number_text(g.x0 + g.nx * g.dx) + ", " +
                                    common::number_text(g.y0 + g.ny * g.dy) + ")");
  }
  // Points every cell along the line: at least half must be on water (a line drawn on a map
  // may cut a bend's bank, but not run beside the river).
  const double step = std::min(g.dx, g.dy);
  const long points = std::max(2L, long(std::ceil(line.length() / step)) + 1);
  long wet = 0;
  for (long k = 0; k < points; ++k) {
    double x, y;
    line.point_at(line.length() * double(k) / double(points - 1), 0, x, y);
    wet += flow.sample(x, y, 0).where == FlowWhere::water;
  }
  if (2 * wet < points)
    throw common::ConfigError(
        file, "/centreline",
        "only " + common::number_text(std::round(100.0 * double(wet) / double(points))) +
            " % of its " + common::number_text(line.length()) +
            " m lies on the reach's water at the start: the leading edge "
            "and the banks are measured along it; draw it down the river");
}

void check_forecast_size(const ForecastConfig& c, const ReachFlow& flow, const Centreline& line,
                         double peak_wind, double memory_bytes, const std::string& file) {
  // Steps and sub-steps: the fastest surface flow at the start (the log law raises the depth's
  // mean by at most about a third) plus the wind's drift.
  const reach::WaterState w = flow.water_at(0);
  double fastest = 0;
  for (size_t k = 0; k < w.h.size(); ++k)
    if (w.h[k] > 0.01) fastest = std::max(fastest, std::hypot(w.hu[k], w.hv[k]) / w.h[k]);
  const double speed = 1.35 * fastest + c.drift.wind_factor * peak_wind;
  const double substeps = std::max(
      1.0, std::ceil(speed * c.time_step / (c.drift.max_cells_per_substep * flow.resolution())));
  const double steps = std::ceil(c.end_time / c.time_step - 1e-9);
  if (steps * substeps > c.max_steps) {
    const std::string key = substeps > 100    ? "/drift/max_cells_per_substep"
                            : c.time_step < 1 ? "/time_step"
                                              : "/end_time";
    throw common::ConfigError(
        file, key,
        "the forecast would take " + common::number_text(steps) + " steps of " +
            common::number_text(c.time_step) + " s to /end_time = " +
            common::number_text(c.end_time) + " s, each of " + common::number_text(substeps) +
            " drift sub-steps (" + common::number_text(speed) + " m/s over " +
            common::number_text(flow.resolution()) + " m cells at /drift/max_cells_per_substep = " +
            common::number_text(c.drift.max_cells_per_substep) +
            "): " + common::number_text(steps * substeps) + " in all, above /max_steps = " +
            common::number_text(c.max_steps) + ": check this value, or raise /max_steps to run it");
  }
  // An ensemble does that work once per member.
  if (c.ensemble && steps * substeps * c.ensemble->members > c.max_steps)
    throw common::ConfigError(
        file, "/ensemble/members",
        common::number_text(c.ensemble->members) + " members of " +
            common::number_text(steps * substeps) + " steps and sub-steps each are " +
            common::number_text(steps * substeps * c.ensemble->members) +
            " in all, above /max_steps = " + common::number_text(c.max_steps) +
            ": fewer members, or raise /max_steps to run them");
  // Memory: the elements (the releases'; a near field's parcels come later) and a snapshot of
  // each at every output.
  double elements = 0;
  for (const auto& r : c.releases) elements += r.elements;
  const double outputs = std::floor(c.end_time / c.output_every) + 2;
  const double element_bytes = elements * (kBytesPerElement + outputs * kBytesPerElementOutput);
  if (element_bytes > memory_bytes)
    throw common::ConfigError(
        file, "/releases",
        common::number_text(elements) + " elements with their snapshots at " +
            common::number_text(outputs) + " outputs need at least " +
            common::number_text(element_bytes / 1e9) + " GB, this process may use " +
            common::number_text(memory_bytes / 1e9) + " GB: fewer elements, or outputs less often");
  // An ensemble's tally: a count per cell of the reach's grid at every output, and the
  // probabilities made of them.
  if (c.ensemble) {
    const double tally_bytes = outputs * double(flow.grid().cells()) * 12;
    if (tally_bytes > memory_bytes)
      throw common::ConfigError(
          file, "/ensemble",
          "the members' tally of " + common::number_text(double(flow.grid().cells())) +
              " cells at " + common::number_text(outputs) + " outputs needs " +
              common::number_text(tally_bytes / 1e9) + " GB, this process may use " +
              common::number_text(memory_bytes / 1e9) + " GB: outputs less often");
  }
  // The bank bins, each with its holdings at every output.
  const double bins = std::ceil(line.length() / c.banks.bin_length) + 1;
  const double bin_bytes = bins * 2 * (64 + outputs * 16);
  if (bins > 1e8 || bin_bytes > memory_bytes)
    throw common::ConfigError(file, "/banks/bin_length",
                              common::number_text(bins) + " bins of " +
                                  common::number_text(c.banks.bin_length) + " m along the " +
                                  common::number_text(line.length()) + " m centreline need " +
                                  common::number_text(bin_bytes / 1e9) +
                                  " GB (and at most 1e8 bins are counted): use longer bins");
}

}  // namespace farfield
