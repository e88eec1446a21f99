#pragma once
// The JSON config of a far-field forecast (`spill-sim forecast --config FILE`): the reach run
// the oil rides on, the river's centreline, the oil, where and how fast it is released, the
// weather, the banks, the watch points, and the time stepping. Every key is declared once below;
// unknown keys and values out of range are errors naming the file and the JSON pointer.
// docs/far_field.md documents them (docs/far_field_reference.md lists every key).

#include <optional>
#include <string>
#include <vector>

#include "common/config_error.h"
#include "common/config_visitors.h"
#include "common/param_spec.h"
#include "farfield/ensemble/ensemble_config.h"
#include "farfield/model/drift.h"
#include "reach/reach_config.h"

namespace farfield {

using common::ConfigError;
using common::param;
using reach::SeriesConfig;

inline void check_point(const std::vector<double>& p, const std::string& file,
                        const std::string& pointer) {
  if (p.size() != 2) throw ConfigError(file, pointer, "expected [x, y] in map coordinates");
}

struct FlowConfig {
  std::string reach_run;
  double start_time = -1;
  double manning = -1;
  double dry_depth = 0.01;
  template <class V>
  void describe(V& v) {
    v.field("reach_run", reach_run,
            param("", "Folder of a finished `spill-sim reach` run, relative to the config's folder")
                .require());
    v.field("start_time", start_time,
            param("s",
                  "The reach run's output time at which the forecast starts (< 0: its last; a "
                  "steady run's last output holds for ever after)"));
    v.field("manning", manning,
            param("s/m^(1/3)", "Manning's n for the drift's log law (< 0: the reach run's)")
                .at_most(reach::kMaxManning));
    v.field("dry_depth", dry_depth,
            param("m", "Shallower water is shore: an element reaching it strands").positive());
  }
};

struct ReleaseConfig {
  std::string name = "release";
  std::vector<double> position;  // point source
  std::vector<double> from, to;  // line source
  double start = 0, end = 0;     // s
  SeriesConfig rate;             // m^3/s of oil
  int elements = 1000;
  template <class V>
  void describe(V& v) {
    v.field("name", name, param("", "Name of the release"));
    v.field("position", position, param("m", "[x, y]: a point source, in map coordinates"));
    v.field("from", from, param("m", "[x, y]: one end of a line source"));
    v.field("to", to, param("m", "[x, y]: its other end"));
    v.field("start", start, param("s", "When the release starts").non_negative());
    v.field("end", end, param("s", "When it ends (= start: all at once)").non_negative());
    v.field("rate", rate,
            param("m^3/s",
                  "Oil released per second, constant or a series (for an instantaneous release: "
                  "the volume, m^3)")
                .require());
    v.field("elements", elements, param("", "Elements that carry the release").at_least(1));
  }
  void check(const std::string& file, const std::string& pointer) const {
    if (position.empty() == from.empty())
      throw ConfigError(file, pointer, "give either position (a point) or from and to (a line)");
    if (!position.empty()) check_point(position, file, pointer + "/position");
    if (!from.empty()) {
      check_point(from, file, pointer + "/from");
      check_point(to, file, pointer + "/to");
    }
    if (end < start) throw ConfigError(file, pointer + "/end", "expected >= start");
  }
};

struct EnvironmentConfig {
  SeriesConfig water_temperature;  // deg C
  SeriesConfig wind_speed;         // m/s at 10 m
  SeriesConfig wind_from;          // deg, where the wind comes from (meteorological)
  std::optional<SeriesConfig> wave_height;
  double fetch = 500;
  bool ice = false;
  bool river_dispersion = false;
  bool sinking = false;
  template <class V>
  void describe(V& v) {
    v.field("water_temperature", water_temperature,
            param("deg C", "Water temperature, constant or a series").require());
    v.field("wind_speed", wind_speed,
            param("m/s", "Wind speed at 10 m, constant or a series").require());
    v.field("wind_from", wind_from,
            param("deg", "Direction the wind blows from, clockwise from north").require());
    v.field("wave_height", wave_height,
            param("m",
                  "Significant wave height for natural dispersion (absent: a river's short "
                  "fetch's, from the wind)"));
    v.field("fetch", fetch,
            param("m",
                  "How far the wind blows over open water to raise the waves when wave_height is "
                  "not given (a river's width, or its straight reach along the wind)")
                .positive());
    v.field("ice", ice, param("", "The river is under ice: no wind drift and no evaporation"));
    v.field("river_dispersion", river_dispersion,
            param("",
                  "Natural dispersion by the river's own turbulence too (Delvigne & Hulsen 1994 "
                  "with the surface dissipation of the bed shear), beside the waves'. Off by "
                  "default: a laboratory law carried over to rivers; run with and without it to "
                  "bracket the budget (docs/far_field.md)"));
    v.field("sinking", sinking,
            param("",
                  "Oil whose weathered density reaches the water's sinks to the bed where it is "
                  "(budget: sunk)"));
  }
};

struct BankClassConfig {
  std::string name;
  double capacity = 0.01;
  double refloat_half_life = 24;
  template <class V>
  void describe(V& v) {
    v.field("name", name, param("", "Name of the class").require());
    v.field("capacity", capacity,
            param("m^3/m", "Oil one metre of this bank holds").non_negative());
    v.field("refloat_half_life", refloat_half_life,
            param("h", "Half of the oil stranded here floats off in this time").positive());
  }
};

struct BankStretchConfig {
  std::string side = "right";
  double from_km = 0, to_km = 0;
  std::string bank_class;
  template <class V>
  void describe(V& v) {
    v.field("side", side,
            param("", "Bank, looking downstream").one_of({"left", "right", "both"}).require());
    v.field("from_km", from_km, param("km", "Start along the centreline").require());
    v.field("to_km", to_km, param("km", "End along the centreline").require());
    v.field("class", bank_class, param("", "Name of the bank class").require());
  }
};

struct BanksConfig {
  double bin_length = 100;
  std::vector<BankClassConfig> classes;
  std::string default_class;
  std::vector<BankStretchConfig> stretches;
  template <class V>
  void describe(V& v) {
    v.field("bin_length", bin_length,
            param("m", "Length of the bank bins oil is counted in").positive());
    v.field("classes", classes, param("", "Bank classes").require());
    v.field("default_class", default_class,
            param("", "Class of every bank not in a stretch").require());
    v.field("stretches", stretches, param("", "Stretches of another class"));
  }
};

struct WatchPointConfig {
  std::string name;
  std::vector<double> position;
  double radius = 50;
  template <class V>
  void describe(V& v) {
    v.field("name", name, param("", "Name (an intake, a boom site)").require());
    v.field("position", position, param("m", "[x, y] in map coordinates").require());
    v.field("radius", radius, param("m", "Oil within this distance has arrived").positive());
  }
  void check(const std::string& file, const std::string& pointer) const {
    check_point(position, file, pointer + "/position");
  }
};

// The oil: a record of the library or a file, and what the config sets over the record.
struct OilChoice {
  std::string name;
  std::optional<double> max_water_content;
  template <class V>
  void describe(V& v) {
    v.field("name", name,
            param("",
                  "An oil of the library (farfield/oils: light_crude, medium_crude, "
                  "diluted_bitumen) or a path to an oil record JSON")
                .require());
    v.field("max_water_content", max_water_content,
            param("",
                  "Largest water fraction of its emulsion, over the record's (measured or "
                  "estimated)")
                .non_negative()
                .at_most(0.95));
  }
};

// The SPH near field whose oil the far field takes over (`spill-sim forecast` runs it first).
struct NearFieldConfig {
  std::string scene;
  std::string run;
  std::vector<std::string> set;
  int elements_per_parcel = 20;
  template <class V>
  void describe(V& v) {
    v.field("scene", scene,
            param("",
                  "A near-field scene inside this reach run (terrain source reach, with a leak), "
                  "run before the far field; relative to the config's folder. Give this or run"));
    v.field("run", run,
            param("",
                  "A finished near-field run folder inside this reach run (of spill-sim run, or "
                  "of spill-infer predict: a learned near field), handed over as a scene's is; "
                  "relative to the config's folder. Give this or scene"));
    v.field("set", set, param("", "Overrides of the scene's values, \"/pointer=value\" each"));
    v.field("elements_per_parcel", elements_per_parcel,
            param("", "Far-field elements each handed-over parcel of oil becomes").at_least(1));
  }
  void check(const std::string& file, const std::string& pointer) const {
    if (scene.empty() == run.empty())
      throw ConfigError(file, pointer + (scene.empty() ? "/scene" : "/run"),
                        "expected either a scene to run or a finished run folder, not " +
                            std::string(scene.empty() ? "neither" : "both"));
    if (!run.empty() && !set.empty())
      throw ConfigError(file, pointer + "/set",
                        "overrides a scene's values, but a finished run's are what it ran with");
  }
};

struct ForecastConfig {
  std::string name = "forecast";
  std::string description;
  FlowConfig flow;
  std::vector<std::vector<double>> centreline;
  OilChoice oil;
  std::vector<ReleaseConfig> releases;
  std::optional<NearFieldConfig> near_field;
  EnvironmentConfig environment;
  DriftSettings drift;
  BanksConfig banks;
  std::vector<WatchPointConfig> watch_points;
  std::optional<EnsembleConfig> ensemble;
  std::string evaporation = "adios";
  double end_time = 21600, time_step = 60, output_every = 1800;
  int seed = 1;
  std::string start_date = "2000-01-01T00:00:00Z";
  int max_steps = 1000000;
  template <class V>
  void describe(V& v) {
    v.field("name", name, param("", "Name of the forecast"));
    v.field("description", description, param("", "What it is"));
    v.field("flow", flow, param("", "The river's flow").require());
    v.field("centreline", centreline,
            param("m", "[[x, y], ...] the river's centreline, upstream to downstream").require());
    v.field("oil", oil,
            param("", "The oil: its name (\"medium_crude\") or {\"name\", \"max_water_content\"}")
                .require());
    v.field("releases", releases,
            param("", "Where and when oil enters directly (a point or a line, a rate over time)"));
    v.field("near_field", near_field,
            param("", "An SPH near field whose oil is handed over as it leaves its box"));
    v.field("environment", environment, param("", "Weather and water").require());
    v.field("drift", drift, param("", "Surface drift and mixing"));
    v.field("banks", banks, param("", "Bank classes and stranding").require());
    v.field("watch_points", watch_points, param("", "Intakes and boom sites"));
    v.field("ensemble", ensemble,
            param("",
                  "Perturbed members run beside the forecast: the probability of oiling per cell "
                  "and bank, arrival quantiles (absent: the forecast alone)"));
    v.field("evaporation", evaporation,
            param("",
                  "adios: ADIOS-2's pseudo-components (wind, slick size, temperature); fingas: "
                  "the oil's Fingas equation (measured in a pan, no wind)")
                .one_of({"adios", "fingas"}));
    v.field("end_time", end_time, param("s", "How long to forecast").positive());
    v.field("time_step", time_step, param("s", "Time step").positive());
    v.field("output_every", output_every, param("s", "Interval of the outputs").positive());
    v.field("seed", seed, param("", "Seed of the random walk").non_negative());
    v.field("start_date", start_date,
            param("",
                  "UTC clock time of forecast time 0, YYYY-MM-DDTHH:MM:SSZ (for the NetCDF "
                  "and the GeoJSON's times)"));
    v.field("max_steps", max_steps,
            param("",
                  "Refuse a forecast whose time steps times the drift's sub-steps (estimated "
                  "from the fastest flow at the start and the strongest wind) exceed this")
                .at_least(1));
  }
  void check(const std::string& file, const std::string& pointer) const {
    if (centreline.size() < 2)
      throw ConfigError(file, pointer + "/centreline", "expected at least 2 points");
    for (size_t k = 0; k < centreline.size(); ++k)
      check_point(centreline[k], file, pointer + "/centreline/" + std::to_string(k));
    if (releases.empty() && !near_field)
      throw ConfigError(file, pointer + "/releases", "expected a release or a near_field");
    if (output_every < time_step)
      throw ConfigError(file, pointer + "/output_every", "expected >= time_step");
  }
};

// Reads `file` with "/pointer=value" overrides; relative paths become relative to its folder.
ForecastConfig load_forecast_config(const std::string& file,
                                    const std::vector<std::string>& overrides);

// The keys as a Markdown table (docs/far_field_reference.md is this).
std::string forecast_reference_markdown();

}  // namespace farfield
