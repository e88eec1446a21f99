#pragma once
// The JSON config of a reach run (`spill-sim reach --config FILE`): the terrain raster, its
// roughness, the inflow and outflow sections, the initial water and how long to run. Every key
// is declared once below; unknown keys and values out of range are errors naming the file and
// the JSON pointer (common/config_visitors.h). docs/reach.md documents them.

#include <optional>
#include <string>
#include <vector>

#include "common/config_error.h"
#include "common/config_visitors.h"
#include "common/param_spec.h"

namespace reach {

using common::ConfigError;
using common::param;

// Manning's n above this is not a roughness of any bed (Chow's tables end near 0.2, dense
// floodplain brush).
constexpr double kMaxManning = 1.0;

// A value over time: a constant, inline (t, value) points, or a CSV column.
struct SeriesConfig {
  std::optional<double> value;
  std::vector<std::vector<double>> points;  // [[t_s, value], ...]
  std::string file;                         // CSV, relative to the config's folder
  std::string time_format = "seconds";      // "seconds", or a strftime format of a date column
  std::string from;                         // the file's time that becomes t = 0 (empty: first)
  int time_column = 0, value_column = 1;
  double scale = 1;  // the file's values are multiplied by it
  template <class V>
  void describe(V& v) {
    v.field("value", value, param("", "A constant value"));
    v.field("points", points, param("s, value", "(time, value) pairs, time increasing"));
    v.field("file", file, param("", "CSV file with a header row, relative to the config's folder"));
    v.field("time_format", time_format,
            param("",
                  "How the file's time column reads: \"seconds\" from the start, or a strftime "
                  "format of a date (e.g. \"%m/%d/%Y %H:%M:%S\")"));
    v.field("from", from,
            param("",
                  "The file's time (as time_format reads it) that becomes t = 0; empty: its "
                  "first row"));
    v.field("time_column", time_column, param("", "Column of the time (from 0)").non_negative());
    v.field("value_column", value_column, param("", "Column of the value (from 0)").non_negative());
    v.field("scale", scale, param("", "Factor applied to the file's values").positive());
  }
  void check(const std::string& file_name, const std::string& pointer) const {
    const int given = int(value.has_value()) + int(!points.empty()) + int(!file.empty());
    if (given != 1)
      throw ConfigError(
          file_name, pointer,
          "give exactly one of value, points and file (got " + std::to_string(given) + ")");
    for (size_t k = 0; k < points.size(); ++k)
      if (points[k].size() != 2)
        throw ConfigError(file_name, pointer + "/points/" + std::to_string(k),
                          "expected [time, value]");
  }
};

// A stretch of the grid's edge, by map coordinates along it: y on the west and east sides, x on
// the south and north ones (the CRS's units).
struct SectionConfig {
  std::string name;
  std::string side = "west";
  double from = 0, to = 0;
  template <class V>
  void describe(V& v) {
    v.field("name", name, param("", "Name in reach.json").require());
    v.field("side", side,
            param("", "Edge of the grid the section lies on")
                .one_of({"west", "east", "south", "north"})
                .require());
    v.field("from", from,
            param("m", "Start of the section along the side (map coordinate)").require());
    v.field("to", to, param("m", "End of the section along the side (map coordinate)").require());
  }
  void check(const std::string& file_name, const std::string& pointer) const {
    if (!(to > from)) throw ConfigError(file_name, pointer + "/to", "expected > from");
  }
};

// Water entering through a section of the grid's edge, or released over an area inside it (a
// river that enters the terrain away from its edge).
struct InflowConfig {
  std::optional<SectionConfig> section;
  std::vector<double> area;  // [x_min, y_min, x_max, y_max]
  std::string name;
  SeriesConfig discharge;
  template <class V>
  void describe(V& v) {
    v.field("section", section, param("", "Where the water enters through the grid's edge"));
    v.field("area", area,
            param("m",
                  "[x_min, y_min, x_max, y_max] in map coordinates: release the water over the "
                  "cells whose centres lie inside, with no momentum (instead of `section`)"));
    v.field("name", name, param("", "Name in reach.json of an area inflow"));
    v.field("discharge", discharge,
            param("m^3/s", "Discharge entering (>= 0), constant or a hydrograph").require());
  }
  void check(const std::string& file_name, const std::string& pointer) const {
    if (section.has_value() == !area.empty())
      throw ConfigError(file_name, pointer, "give exactly one of section and area");
    if (!area.empty() && (area.size() != 4 || !(area[2] > area[0]) || !(area[3] > area[1])))
      throw ConfigError(file_name, pointer + "/area",
                        "expected [x_min, y_min, x_max, y_max] with max > min");
    if (!area.empty() && name.empty())
      throw ConfigError(file_name, pointer + "/name", "an area inflow needs a name");
  }
};

struct OutflowConfig {
  SectionConfig section;
  std::string kind = "normal_depth";
  double slope = 0.001;
  std::optional<SeriesConfig> stage;
  template <class V>
  void describe(V& v) {
    v.field("section", section, param("", "Where the water leaves").require());
    v.field("kind", kind,
            param("",
                  "normal_depth: the depth outside is the normal depth at `slope`; stage: the "
                  "water level outside is `stage`; free: the outside copies the inside")
                .one_of({"normal_depth", "stage", "free"}));
    v.field("slope", slope, param("", "Bed slope beyond the section (normal_depth)").positive());
    v.field("stage", stage, param("m", "Water level outside (stage), constant or a series"));
  }
  void check(const std::string& file_name, const std::string& pointer) const {
    if (kind == "stage" && !stage)
      throw ConfigError(file_name, pointer + "/stage", "a stage outflow needs a stage");
  }
};

// A channel carved into a terrain that shows the water surface rather than the bed (LiDAR does
// not see through water): along the centreline, the bed is lowered to a trapezoid of the given
// bottom width, depth below the bank line and side slope, wherever that is below the terrain.
struct ChannelConfig {
  std::vector<std::vector<double>> centreline;  // [[x, y], ...] map coordinates, downstream
  double bottom_width = 10, depth = 1, side_slope = 2;
  template <class V>
  void describe(V& v) {
    v.field("centreline", centreline,
            param("m", "Points [x, y] along the channel's centre, in map coordinates").require());
    v.field("bottom_width", bottom_width,
            param("m", "Width of the channel's flat bottom").positive());
    v.field("depth", depth,
            param("m", "Depth of the bottom below the terrain on the centreline").positive());
    v.field("side_slope", side_slope,
            param("", "Horizontal run per unit of rise of the banks (2: 1 in 2)").non_negative());
  }
  void check(const std::string& file_name, const std::string& pointer) const {
    if (centreline.size() < 2)
      throw ConfigError(file_name, pointer + "/centreline", "expected at least 2 points");
    for (size_t k = 0; k < centreline.size(); ++k)
      if (centreline[k].size() != 2)
        throw ConfigError(file_name, pointer + "/centreline/" + std::to_string(k),
                          "expected [x, y]");
  }
};

struct TerrainConfig {
  std::string file;
  int coarsen = 1;
  std::vector<double> window;  // [x_min, y_min, x_max, y_max]
  double manning = 0.035;
  std::string manning_file;
  std::string crs;
  std::optional<ChannelConfig> channel;
  template <class V>
  void describe(V& v) {
    v.field("file", file,
            param("",
                  "Elevation raster (any format GDAL reads: GeoTIFF, ESRI ASCII, ...), relative "
                  "to the config's folder")
                .require());
    v.field("coarsen", coarsen,
            param("", "Average blocks of this many cells a side (1: the raster's own grid)")
                .at_least(1));
    v.field("window", window,
            param("m", "[x_min, y_min, x_max, y_max] in map coordinates: run on this part only"));
    v.field("manning", manning,
            param("s/m^(1/3)", "Manning's n everywhere (dense brush is about 0.2)")
                .non_negative()
                .at_most(kMaxManning));
    v.field("manning_file", manning_file,
            param("", "Raster of Manning's n on the terrain's grid (instead of `manning`)"));
    v.field("crs", crs,
            param("",
                  "Coordinate reference system of the raster when its file has none, or to "
                  "override it (e.g. \"EPSG:2193\"); it must be projected, in metres"));
    v.field("channel", channel, param("", "A channel carved along a centreline"));
  }
  void check(const std::string& file_name, const std::string& pointer) const {
    if (!window.empty() &&
        (window.size() != 4 || !(window[2] > window[0]) || !(window[3] > window[1])))
      throw ConfigError(file_name, pointer + "/window",
                        "expected [x_min, y_min, x_max, y_max] with max > min");
  }
};

struct ReachConfig {
  std::string name = "reach";
  std::string description;
  TerrainConfig terrain;
  std::vector<InflowConfig> inflows;
  std::vector<OutflowConfig> outflows;
  std::optional<double> initial_level;
  double end_time = 3600, output_every = 600;
  double steady_tolerance = 0, steady_window = 600;
  double cfl = 0.45, dry_depth = 1e-4, max_dt = 10;
  int max_steps = 10000000;
  template <class V>
  void describe(V& v) {
    v.field("name", name, param("", "Name of the run"));
    v.field("description", description, param("", "What the run is"));
    v.field("terrain", terrain, param("", "The terrain and its roughness").require());
    v.field("inflows", inflows, param("", "Sections where water enters"));
    v.field("outflows", outflows, param("", "Sections where water leaves"));
    v.field("initial_level", initial_level,
            param("m", "Still water up to this level at the start (absent: dry)"));
    v.field("end_time", end_time, param("s", "Simulated time to run").positive());
    v.field("output_every", output_every,
            param("s", "Interval of the rasters and pictures written").positive());
    v.field("steady_tolerance", steady_tolerance,
            param("m/s",
                  "Stop early once the depths drift slower than this (the RMS over the cells "
                  "deeper than 1 cm of their change over steady_window, divided by it) and the "
                  "net discharge through the sections is within 1 % of the inflow (0: run to "
                  "end_time)")
                .non_negative());
    v.field("steady_window", steady_window,
            param("s", "The interval over which the steady-state residual is measured").positive());
    v.field("cfl", cfl, param("", "Courant number of the time step").positive().at_most(0.5));
    v.field("dry_depth", dry_depth,
            param("m", "Shallower water holds no velocity and counts as dry").positive());
    v.field("max_dt", max_dt, param("s", "Longest time step").positive());
    v.field("max_steps", max_steps,
            param("",
                  "Refuse a run estimated (from the inflows' critical flow and the initial "
                  "water) to need more time steps, and stop one that takes more; raise it for "
                  "a long run on a fine grid")
                .at_least(1));
  }
};

// Reads `file` with "/pointer=value" overrides; relative paths in it become relative to the
// file's folder. Throws ConfigError naming the file and the key.
ReachConfig load_reach_config(const std::string& file, const std::vector<std::string>& overrides);

// The keys of a reach config as a Markdown table (docs/reach_reference.md is this).
std::string reach_reference_markdown();

}  // namespace reach
