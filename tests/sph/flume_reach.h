#pragma once
// A reach run to put near fields in, for tests: a trapezoidal flume written as a GeoTIFF (NZTM2000)
// and run to its steady state by the shallow-water solver, and a near-field scene of a 2 m box of
// it. Used by the near field's own tests and by the learned near field's hand-over test.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "reach/raster.h"
#include "reach/reach_run.h"

namespace flume_reach {

constexpr double kX0 = 1771000, kY0 = 5472000;  // NZTM2000, the flume's south-west corner
constexpr double kDischarge = 0.1;              // m^3/s

// The flume: 16 m long, falling 1 in 1000 to the east; a channel 0.8 m wide at the bottom with
// banks of slope 1 rising 0.4 m, its axis 1.2 m from the south edge, flat ground beyond.
inline double bed(double x, double y) {
  const double d = std::abs(y - 1.2);
  return -0.001 * x + std::clamp(d - 0.4, 0.0, 0.4);
}

// Writes the flume into `dir` and runs it to its steady state into dir/flume_run; returns the
// reach run's summary.
inline nlohmann::json run(const std::filesystem::path& dir) {
  reach::Raster r;
  r.grid.nx = 160, r.grid.ny = 24, r.grid.dx = r.grid.dy = 0.1;
  r.grid.x0 = kX0, r.grid.y0 = kY0;
  for (int j = 0; j < r.grid.ny; ++j)
    for (int i = 0; i < r.grid.nx; ++i)
      r.values.push_back(bed(r.grid.x(i) - kX0, r.grid.y(j) - kY0));
  r.crs_wkt = reach::crs_wkt_of("EPSG:2193");
  reach::write_geotiff((dir / "flume.tif").string(), r);
  const nlohmann::json section = {{"from", kY0 + 0.4}, {"to", kY0 + 2.0}};
  nlohmann::json inflow_section = section, outflow_section = section;
  inflow_section.update({{"name", "upstream"}, {"side", "west"}});
  outflow_section.update({{"name", "downstream"}, {"side", "east"}});
  const nlohmann::json config = {
      {"name", "flume"},
      {"terrain", {{"file", "flume.tif"}, {"manning", 0.012}}},
      {"inflows", {{{"section", inflow_section}, {"discharge", {{"value", kDischarge}}}}}},
      {"outflows", {{{"section", outflow_section}, {"kind", "normal_depth"}, {"slope", 0.001}}}},
      {"end_time", 1200},
      {"output_every", 1200},
      {"steady_tolerance", 1e-5},
      {"steady_window", 60}};
  std::ofstream(dir / "reach.json") << config.dump(2);
  std::ostringstream log;
  reach::ReachRunOptions o;
  o.config_file = (dir / "reach.json").string();
  o.out_dir = (dir / "flume_run").string();
  o.log = &log;
  return reach::run_reach(o);
}

// The near field: a box 2 m long and 2 m wide around the flume's axis 7 m downstream, its
// upstream end closed by a wall, at 2 cm particles, in the reach run dir/flume_run (a scene
// written into dir).
inline nlohmann::json scene() {
  return {
      {"name", "flume_near_field"},
      {"solver", "mtdf"},
      {"particle_radius", 0.02},
      {"end_time", 3.0},
      {"materials",
       {{"water", {{"density", 1000}, {"viscosity", 0.001}}},
        {"oil", {{"density", 940}, {"viscosity", 0.004}}}}},
      {"output", {{"frame_dt", 0.05}}},
      {"terrain",
       {{"source", "reach"},
        {"reach",
         {{"run", "flume_run"},
          {"centre", {kX0 + 8, kY0 + 1.2}},
          {"length", 2},
          {"width", 2},
          {"cell_size", 0.02}}},
        {"fill_water", true}}},
      {"flow", {{"inflow_x", 0.025}, {"outflow_x", 1.8}, {"buffer", 0.15}}},
      {"boxes", {{{"min", {-0.2, -1.2, -0.5}}, {"max", {0, 1.2, 0.5}}, {"fluid_side", "outside"}}}},
      {"domain", {{"min", {-0.3, -1.3, -0.6}}, {"max", {2.3, 1.3, 0.6}}}}};
}

// A leak in the box's centre 0.8 m from its inflow, of `rate` m^3/s from 0.2 s for `duration` s:
// the scene's "leaks".
inline nlohmann::json leaks(double rate, double duration) {
  return {{{"x", 0.8},
           {"position", "centre"},
           {"rate", rate},
           {"speed", 0.3},
           {"start", 0.2},
           {"duration", duration}}};
}

// A far-field forecast of a minute on the flume's flow (dir/flume_run, relative to a config in
// dir), calm, concrete banks, with `near_field` as its near field.
inline nlohmann::json forecast(const nlohmann::json& near_field) {
  return {{"flow", {{"reach_run", "flume_run"}}},
          {"centreline", {{kX0 + 0.5, kY0 + 1.2}, {kX0 + 15.5, kY0 + 1.2}}},
          {"oil", "medium_crude"},
          {"near_field", near_field},
          {"environment",
           {{"water_temperature", {{"value", 15}}},
            {"wind_speed", {{"value", 0}}},
            {"wind_from", {{"value", 0}}}}},
          {"banks", {{"classes", {{{"name", "concrete"}}}}, {"default_class", "concrete"}}},
          {"end_time", 60},
          {"time_step", 1},
          {"output_every", 30}};
}

}  // namespace flume_reach
