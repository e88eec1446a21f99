#include "farfield/forecast_setup.h"

#include <iomanip>
#include <map>
#include <memory>
#include <sstream>

#include "common/memory_limit.h"
#include "farfield/flows/reach_flow.h"
#include "farfield/forecast_checks.h"
#include "reach/series.h"

namespace farfield {

namespace {

std::string point_text(double x, double y) {
  std::ostringstream s;
  s.precision(10);
  s << "(" << x << ", " << y << ")";
  return s.str();
}

// Seconds since the epoch of "YYYY-MM-DDTHH:MM:SSZ"; false when it does not read so.
bool parse_utc(const std::string& text, std::time_t& out) {
  std::tm tm{};
  std::istringstream in(text);
  in >> std::get_time(&tm, "%Y-%m-%dT%H:%M:%S");
  if (in.fail()) return false;
  char zone = 0;
  in >> zone;
  if (zone != 'Z' || in.peek() != EOF) return false;
  out = timegm(&tm);
  return true;
}

// A series that must hold over the whole forecast: constants do; points and files must span it.
reach::Hydrograph covering_series(const SeriesConfig& s, double end, const std::string& file,
                                  const std::string& pointer, bool non_negative) {
  const reach::Hydrograph h = reach::load_series(s, file, pointer);
  if (!s.value) {
    const double first = h.points().front().first, last = h.points().back().first;
    if (first > 0 || last < end)
      throw ConfigError(file, pointer,
                        "the series covers " + std::to_string(first) + " to " +
                            std::to_string(last) + " s, but the forecast runs from 0 to " +
                            std::to_string(end) + " s: extend it");
  }
  if (non_negative)
    for (const auto& [t, v] : h.points())
      if (v < 0)
        throw ConfigError(
            file, pointer,
            "a negative value (" + std::to_string(v) + " at " + std::to_string(t) + " s)");
  return h;
}

std::shared_ptr<ReachFlow> load_flow(const ForecastConfig& c, const std::string& file) {
  ReachFlowRequest request;
  request.run_dir = c.flow.reach_run;
  request.start_time = c.flow.start_time;
  request.manning = c.flow.manning;
  request.dry_depth = c.flow.dry_depth;
  request.config_file = file;
  request.pointer = "/flow";
  auto flow = std::make_shared<ReachFlow>(request);
  if (flow->known_until() < c.end_time)
    throw ConfigError(file, "/end_time",
                      "the reach run's flow is known to " + std::to_string(flow->known_until()) +
                          " s after the start and is not steady: shorten the forecast or run the "
                          "reach longer");
  return flow;
}

// Refuses a point off the reach's grid or, where `on_water`, on its dry land at the start.
void check_on_reach(const ReachFlow& flow, const std::vector<double>& p, bool on_water,
                    const std::string& file, const std::string& pointer,
                    const std::string& run_dir) {
  const reach::Grid& g = flow.grid();
  const FlowSample here = flow.sample(p[0], p[1], 0);
  if (here.where == FlowWhere::outside)
    throw ConfigError(
        file, pointer,
        point_text(p[0], p[1]) + " lies outside the reach (" + point_text(g.x0, g.y0) + " to " +
            point_text(g.x0 + g.nx * g.dx, g.y0 + g.ny * g.dy) + ", " + run_dir + ")");
  if (on_water && here.where != FlowWhere::water)
    throw ConfigError(file, pointer,
                      point_text(p[0], p[1]) + " is not on the reach's water (depth " +
                          std::to_string(here.depth) + " m)");
}

Banks build_banks(const BanksConfig& c, const Centreline& centreline, const std::string& file) {
  std::vector<BankClass> classes;
  std::map<std::string, int> class_index;
  for (size_t k = 0; k < c.classes.size(); ++k) {
    const auto& b = c.classes[k];
    if (class_index.count(b.name))
      throw ConfigError(file, "/banks/classes/" + std::to_string(k) + "/name",
                        "a second class named \"" + b.name + "\"");
    class_index[b.name] = int(k);
    classes.push_back({b.name, b.capacity, b.refloat_half_life * 3600});
  }
  const auto class_of = [&](const std::string& name, const std::string& pointer) {
    const auto it = class_index.find(name);
    if (it == class_index.end())
      throw ConfigError(file, pointer, "no bank class named \"" + name + "\"");
    return it->second;
  };
  std::vector<BankStretch> stretches;
  for (size_t k = 0; k < c.stretches.size(); ++k) {
    const auto& st = c.stretches[k];
    const std::string at = "/banks/stretches/" + std::to_string(k);
    const int index = class_of(st.bank_class, at + "/class");
    if (!(st.to_km > st.from_km)) throw ConfigError(file, at + "/to_km", "expected > from_km");
    for (const BankSide side : {BankSide::right, BankSide::left})
      if (st.side == "both" || (st.side == "left") == (side == BankSide::left))
        stretches.push_back({side, st.from_km * 1000, st.to_km * 1000, index});
  }
  const int default_class = class_of(c.default_class, "/banks/default_class");
  return Banks(centreline, c.bin_length, classes, default_class, stretches);
}

Environment build_environment(const ForecastConfig& c, const std::string& file) {
  Environment env;
  const auto& e = c.environment;
  env.water_temperature_c = covering_series(e.water_temperature, c.end_time, file,
                                            "/environment/water_temperature", false);
  check_water_temperature(env.water_temperature_c, file, "/environment/water_temperature");
  env.wind_speed = covering_series(e.wind_speed, c.end_time, file, "/environment/wind_speed", true);
  env.wind_from_deg =
      covering_series(e.wind_from, c.end_time, file, "/environment/wind_from", false);
  if (e.wave_height)
    env.wave_height =
        covering_series(*e.wave_height, c.end_time, file, "/environment/wave_height", true);
  env.fetch = e.fetch;
  env.ice = e.ice;
  env.river_dispersion = e.river_dispersion;
  env.sinking = e.sinking;
  return env;
}

std::vector<ReleaseSpec> build_releases(const ForecastConfig& c, const ReachFlow& flow,
                                        const std::string& file) {
  std::vector<ReleaseSpec> out;
  for (size_t k = 0; k < c.releases.size(); ++k) {
    const ReleaseConfig& r = c.releases[k];
    const std::string at = "/releases/" + std::to_string(k);
    const bool point = !r.position.empty();
    const std::vector<double>& a = point ? r.position : r.from;
    const std::vector<double>& b = point ? r.position : r.to;
    check_on_reach(flow, a, true, file, at + (point ? "/position" : "/from"), c.flow.reach_run);
    check_on_reach(flow, b, true, file, at + (point ? "/position" : "/to"), c.flow.reach_run);
    ReleaseSpec spec;
    spec.name = r.name;
    spec.x0 = a[0];
    spec.y0 = a[1];
    spec.x1 = b[0];
    spec.y1 = b[1];
    spec.start = r.start;
    spec.end = r.end;
    if (r.start > c.end_time)
      throw ConfigError(file, at + "/start", "starts after the forecast's end");
    spec.rate = covering_series(r.rate, r.end, file, at + "/rate", true);
    spec.elements = r.elements;
    out.push_back(spec);
  }
  return out;
}

std::vector<WatchPoint> build_watch_points(const ForecastConfig& c, const ReachFlow& flow,
                                           const Centreline& centreline, const std::string& file) {
  std::vector<WatchPoint> out;
  for (size_t k = 0; k < c.watch_points.size(); ++k) {
    const auto& w = c.watch_points[k];
    check_on_reach(flow, w.position, false, file,
                   "/watch_points/" + std::to_string(k) + "/position", c.flow.reach_run);
    WatchPoint p;
    p.name = w.name;
    p.x = w.position[0];
    p.y = w.position[1];
    p.radius = w.radius;
    p.km = centreline.locate(p.x, p.y).along_m;
    out.push_back(p);
  }
  return out;
}

}  // namespace

ForecastSetup build_forecast(const ForecastConfig& c, const std::string& file) {
  ForecastSetup out;
  out.config = c;
  if (!parse_utc(c.start_date, out.start_epoch))
    throw ConfigError(file, "/start_date",
                      "expected YYYY-MM-DDTHH:MM:SSZ, got \"" + c.start_date + "\"");
  FarFieldSetup& s = out.model;
  // An oil of the forecast or of its ensemble, refused unless it floats.
  const auto floating_oil = [&file](const std::string& name, const std::string& pointer) {
    OilRecord oil = load_oil(name, SPILL_OIL_LIBRARY, file, pointer);
    if (!(oil.density < 1000))
      throw ConfigError(file, pointer,
                        oil.name + " (" + std::to_string(oil.density) +
                            " kg/m^3) is not lighter than fresh water: it would not float");
    return oil;
  };
  s.oil = floating_oil(c.oil.name, "/oil");
  if (c.oil.max_water_content) {
    s.oil.max_water_fraction = *c.oil.max_water_content;
    s.oil.max_water_source = "set in the config (/oil/max_water_content)";
  }
  if (c.ensemble)
    for (size_t k = 0; k < c.ensemble->oils.size(); ++k)
      out.ensemble_oils.push_back(
          floating_oil(c.ensemble->oils[k], "/ensemble/oils/" + std::to_string(k)));
  const std::shared_ptr<ReachFlow> flow = load_flow(c, file);
  s.flow = flow;
  s.dry_depth = c.flow.dry_depth;

  std::vector<std::pair<double, double>> line;
  for (const auto& p : c.centreline) line.emplace_back(p[0], p[1]);
  try {
    s.centreline = Centreline(line);
  } catch (const std::invalid_argument& e) {
    throw ConfigError(file, "/centreline", e.what());
  }
  check_centreline_on_water(s.centreline, c, *flow, file);
  // The weather first: the size check reads the wind, and the banks are sized after it.
  s.environment = build_environment(c, file);
  check_forecast_size(c, *flow, s.centreline, s.environment.wind_speed.peak(),
                      common::physical_memory_bytes(), file);
  s.banks = build_banks(c.banks, s.centreline, file);
  s.drift = c.drift;
  s.drift.seed = std::uint64_t(c.seed);
  s.releases = build_releases(c, *flow, file);
  // A continuous release's oil of one output interval spreads as one slick: the interval a
  // reader of the outputs sees, and no more a matter of the time step.
  s.slick_interval = c.output_every;
  s.weathering.fingas = c.evaporation == "fingas";
  out.watch_points = build_watch_points(c, *flow, s.centreline, file);
  return out;
}

}  // namespace farfield
