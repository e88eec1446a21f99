#include "farfield/forecast_run.h"

#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>

#include "common/exit_codes.h"
#include "common/image_writer.h"
#include "common/memory_limit.h"
#include "common/output_folder.h"
#include "common/progress.h"
#include "common/svg_plot.h"
#include "farfield/forecast_checks.h"
#include "farfield/outputs/forecast_map.h"
#include "farfield/outputs/geojson_output.h"
#include "farfield/outputs/lon_lat.h"
#include "farfield/outputs/netcdf_output.h"
#include "farfield/flows/reach_flow.h"
#include "reach/series.h"

namespace farfield {

namespace fs = std::filesystem;

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

std::string utc_text(std::time_t t) {
  std::tm tm{};
  gmtime_r(&t, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return text;
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

}  // namespace

ForecastSetup build_forecast(const ForecastConfig& c, const std::string& file) {
  ForecastSetup out;
  out.config = c;
  FarFieldSetup& s = out.model;
  std::time_t start = 0;
  if (!parse_utc(c.start_date, start))
    throw ConfigError(file, "/start_date",
                      "expected YYYY-MM-DDTHH:MM:SSZ, got \"" + c.start_date + "\"");

  s.oil = load_oil(c.oil, SPILL_OIL_LIBRARY, file, "/oil");
  if (!(s.oil.density < 1000))
    throw ConfigError(file, "/oil",
                      s.oil.name + " (" + std::to_string(s.oil.density) +
                          " kg/m^3) is not lighter than fresh water: it would not float");

  ReachFlowRequest flow;
  flow.run_dir = c.flow.reach_run;
  flow.start_time = c.flow.start_time;
  flow.manning = c.flow.manning;
  flow.dry_depth = c.flow.dry_depth;
  flow.config_file = file;
  flow.pointer = "/flow";
  auto reach_flow = std::make_shared<ReachFlow>(flow);
  if (reach_flow->known_until() < c.end_time)
    throw ConfigError(file, "/end_time",
                      "the reach run's flow is known to " +
                          std::to_string(reach_flow->known_until()) +
                          " s after the start and is not steady: shorten the forecast or run the "
                          "reach longer");
  s.flow = reach_flow;
  s.dry_depth = c.flow.dry_depth;
  const reach::Grid& g = reach_flow->grid();
  const auto inside = [&](const std::vector<double>& p, const std::string& pointer, bool on_water) {
    const FlowSample here = reach_flow->sample(p[0], p[1], 0);
    if (here.where == FlowWhere::outside)
      throw ConfigError(
          file, pointer,
          point_text(p[0], p[1]) + " lies outside the reach (" + point_text(g.x0, g.y0) + " to " +
              point_text(g.x0 + g.nx * g.dx, g.y0 + g.ny * g.dy) + ", " + c.flow.reach_run + ")");
    if (on_water && here.where != FlowWhere::water)
      throw ConfigError(file, pointer,
                        point_text(p[0], p[1]) + " is not on the reach's water (depth " +
                            std::to_string(here.depth) + " m)");
  };

  std::vector<std::pair<double, double>> line;
  for (const auto& p : c.centreline) line.emplace_back(p[0], p[1]);
  try {
    s.centreline = Centreline(line);
  } catch (const std::invalid_argument& e) {
    throw ConfigError(file, "/centreline", e.what());
  }
  check_centreline_on_water(s.centreline, c, *reach_flow, file);

  // Banks.
  std::vector<BankClass> classes;
  std::map<std::string, int> class_index;
  for (size_t k = 0; k < c.banks.classes.size(); ++k) {
    const auto& b = c.banks.classes[k];
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
  for (size_t k = 0; k < c.banks.stretches.size(); ++k) {
    const auto& st = c.banks.stretches[k];
    const std::string at = "/banks/stretches/" + std::to_string(k);
    const int index = class_of(st.bank_class, at + "/class");
    if (!(st.to_km > st.from_km)) throw ConfigError(file, at + "/to_km", "expected > from_km");
    for (const BankSide side : {BankSide::right, BankSide::left})
      if (st.side == "both" || (st.side == "left") == (side == BankSide::left))
        stretches.push_back({side, st.from_km * 1000, st.to_km * 1000, index});
  }
  // Weather (first: the size check below reads the wind).
  Environment& env = s.environment;
  env.water_temperature_c = covering_series(c.environment.water_temperature, c.end_time, file,
                                            "/environment/water_temperature", false);
  check_water_temperature(env.water_temperature_c, file, "/environment/water_temperature");
  env.wind_speed =
      covering_series(c.environment.wind_speed, c.end_time, file, "/environment/wind_speed", true);
  env.wind_from_deg =
      covering_series(c.environment.wind_from, c.end_time, file, "/environment/wind_from", false);
  if (c.environment.wave_height)
    env.wave_height = covering_series(*c.environment.wave_height, c.end_time, file,
                                      "/environment/wave_height", true);
  env.ice = c.environment.ice;
  check_forecast_size(c, *reach_flow, s.centreline, env.wind_speed.peak(),
                      common::physical_memory_bytes(), file);
  s.banks = Banks(s.centreline, c.banks.bin_length, classes,
                  class_of(c.banks.default_class, "/banks/default_class"), stretches);
  s.drift = c.drift;
  s.drift.seed = std::uint64_t(c.seed);

  // Releases.
  for (size_t k = 0; k < c.releases.size(); ++k) {
    const ReleaseConfig& r = c.releases[k];
    const std::string at = "/releases/" + std::to_string(k);
    ReleaseSpec spec;
    spec.name = r.name;
    const std::vector<double>& a = r.position.empty() ? r.from : r.position;
    const std::vector<double>& b = r.position.empty() ? r.to : r.position;
    inside(a, at + (r.position.empty() ? "/from" : "/position"), true);
    inside(b, at + (r.position.empty() ? "/to" : "/position"), true);
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
    s.releases.push_back(spec);
  }

  for (size_t k = 0; k < c.watch_points.size(); ++k) {
    const auto& w = c.watch_points[k];
    inside(w.position, "/watch_points/" + std::to_string(k) + "/position", false);
    WatchPoint p;
    p.name = w.name;
    p.x = w.position[0];
    p.y = w.position[1];
    p.radius = w.radius;
    p.km = s.centreline.locate(p.x, p.y).along_m;
    out.watch_points.push_back(p);
  }
  return out;
}

namespace {

ElementSnapshot element_snapshot(const FarFieldModel& model, const LonLat& lon_lat,
                                 double water_temperature_c, double water_density) {
  const Elements& el = model.elements();
  const OilRecord& oil = model.setup().oil;
  ElementSnapshot s;
  s.t_s = model.time();
  const size_t n = el.size();
  for (auto* v : {&s.lon, &s.lat, &s.x, &s.y, &s.mass_oil, &s.mass_evaporated, &s.mass_dispersed,
                  &s.water_fraction, &s.thickness, &s.density, &s.viscosity, &s.age})
    v->resize(n);
  s.status.resize(n);
  for (size_t e = 0; e < n; ++e) {
    double lon, lat;
    lon_lat.convert(el.x[e], el.y[e], lon, lat);
    s.lon[e] = float(lon);
    s.lat[e] = float(lat);
    s.x[e] = float(el.x[e]);
    s.y[e] = float(el.y[e]);
    s.status[e] = int(el.state[e]);
    s.mass_oil[e] = float(el.oil_mass(e));
    s.mass_evaporated[e] = float(el.evaporated_mass[e]);
    s.mass_dispersed[e] = float(el.dispersed_mass[e]);
    s.water_fraction[e] = float(el.water_fraction[e]);
    s.thickness[e] = float(model.thickness(e));
    const double y = el.water_fraction[e];
    s.density[e] = float(y * water_density + (1 - y) * oil_density(oil, el, e));
    s.viscosity[e] = float(emulsion_viscosity(oil, el, e, water_temperature_c));
    s.age[e] = float(el.age[e]);
  }
  return s;
}

ShoreSnapshot shore_snapshot(const FarFieldModel& model) {
  const FarFieldSetup& setup = model.setup();
  const Elements& el = model.elements();
  ShoreSnapshot s;
  s.t_s = model.time();
  s.held_m3 = model.bank_held();
  s.mean_offset.assign(s.held_m3.size(), 0.0);
  std::vector<int> count(s.held_m3.size(), 0);
  for (size_t e = 0; e < el.size(); ++e) {
    if (el.state[e] != ElementState::stranded) continue;
    const size_t bin = size_t(el.bank_segment[e]);
    s.mean_offset[bin] += setup.centreline.locate(el.x[e], el.y[e]).offset_m;
    ++count[bin];
  }
  for (size_t b = 0; b < count.size(); ++b)
    if (count[b]) s.mean_offset[b] /= count[b];
  return s;
}

void write_budget(const fs::path& dir, const nlohmann::json& outputs) {
  std::ofstream csv(dir / "budget.csv");
  csv << "t_s,released_kg,floating_kg,stranded_kg,evaporated_kg,dispersed_kg,left_reach_kg,"
         "closure_error\n";
  csv.precision(12);
  std::vector<common::PlotSeries> series = {{"floating", {}, {}},
                                            {"stranded", {}, {}},
                                            {"evaporated", {}, {}},
                                            {"dispersed", {}, {}},
                                            {"left the reach", {}, {}}};
  const char* keys[] = {"floating", "stranded", "evaporated", "dispersed", "left_reach"};
  for (const auto& o : outputs) {
    const auto& b = o.at("budget_kg");
    csv << o.at("t_s").get<double>() << "," << b.at("released").get<double>();
    for (const char* k : keys) csv << "," << b.at(k).get<double>();
    csv << "," << b.at("closure_error").get<double>() << "\n";
    for (size_t k = 0; k < series.size(); ++k) {
      series[k].x.push_back(o.at("t_s").get<double>() / 3600);
      series[k].y.push_back(o.at("budget_fraction").at(keys[k]).get<double>());
    }
  }
  if (!csv) throw std::runtime_error((dir / "budget.csv").string() + ": could not write");
  common::write_line_plot((dir / "budget.svg").string(), "Where the released oil is", "time (h)",
                          "fraction of the oil released", series, false);
}

}  // namespace

nlohmann::json run_forecast(const ForecastRunOptions& o) {
  const auto wall_start = std::chrono::steady_clock::now();
  const ForecastConfig config = load_forecast_config(o.config_file, o.overrides);
  ForecastSetup setup = build_forecast(config, o.config_file);
  common::OutputFolderPolicy policy;
  policy.markers = {"forecast.json"};
  policy.replace = o.force;
  policy.inputs = {fs::path(o.config_file), fs::path(config.flow.reach_run)};
  policy.log = o.log;
  common::OutputFolder folder(o.out_dir, policy);
  const fs::path dir = folder.staging();
  if (o.pictures) fs::create_directories(dir / "png");

  const auto& flow = static_cast<const ReachFlow&>(*setup.model.flow);
  const LonLat lon_lat(flow.crs_wkt());
  std::time_t start = 0;
  parse_utc(config.start_date, start);
  FarFieldModel model(setup.model);
  std::vector<WatchPoint>& points = setup.watch_points;

  // Fixed colour scales for the pictures: the deepest water and fastest flow at the start.
  double depth_scale = 0.5, speed_scale = 0.5;
  {
    const reach::WaterState w = flow.water_at(0);
    for (size_t c = 0; c < w.h.size(); ++c)
      if (w.h[c] > 0.01) {
        depth_scale = std::max(depth_scale, w.h[c]);
        speed_scale = std::max(speed_scale, std::hypot(w.hu[c], w.hv[c]) / w.h[c]);
      }
  }

  nlohmann::json outputs = nlohmann::json::array();
  std::vector<SlickSnapshot> slicks;
  std::vector<ShoreSnapshot> shores;
  std::vector<ElementSnapshot> snapshots;
  const auto output = [&] {
    const double t = model.time();
    nlohmann::json record = forecast_record(model, flow.grid(), points);
    record["time"] = utc_text(start + std::time_t(std::lround(t)));
    outputs.push_back(record);
    slicks.push_back({t, record["time"], oiled_cells(model, flow.grid())});
    ShoreSnapshot shore = shore_snapshot(model);
    shore.clock = record["time"];
    shores.push_back(std::move(shore));
    const WeatherNow w = setup.model.environment.weather_at(t);
    snapshots.push_back(element_snapshot(model, lon_lat, w.water_temperature_c, w.water_density));
    if (o.stop && o.stop->load())
      throw common::Interrupted("forecast interrupted; nothing written");
    if (o.pictures) {
      char name[64];
      std::snprintf(name, sizeof name, "png/map_%05zu.png", outputs.size() - 1);
      outputs.back()["map"] = name;
      common::write_png((dir / name).string(),
                        draw_forecast_map(flow, model, points, depth_scale, speed_scale));
    }
  };

  const long steps = long(std::ceil(config.end_time / config.time_step - 1e-9));
  const long every = std::max(1L, long(std::lround(config.output_every / config.time_step)));
  common::ProgressReporter progress(o.log ? *o.log : std::cerr, o.terminal, steps, "forecast");
  if (config.near_field && o.handover.empty())
    throw ConfigError(o.config_file, "/near_field",
                      "no oil was handed over from the near field (run it with spill-sim "
                      "forecast, which runs the near field first)");
  output();
  double worst_closure = 0, handed_over_m3 = 0;
  size_t next_parcel = 0;
  for (long k = 1; k <= steps; ++k) {
    if (o.stop && o.stop->load()) throw common::Interrupted("forecast interrupted");
    const double dt = std::min(config.time_step, config.end_time - model.time());
    // The near field's oil that left its box during this step joins the far field now.
    for (; next_parcel < o.handover.size() && o.handover[next_parcel].t < model.time() + dt;
         ++next_parcel) {
      // Each parcel as several elements, so that the mixing spreads it as a cloud.
      const HandoverParcel& p = o.handover[next_parcel];
      const int n = config.near_field ? config.near_field->elements_per_parcel : 1;
      for (int k = 0; k < n; ++k)
        model.add_element(p.x, p.y, p.volume / n * setup.model.oil.density, p.area / n);
      handed_over_m3 += p.volume;
    }
    model.step(dt);
    update_arrivals(model, points);
    worst_closure = std::max(worst_closure, model.budget().closure_error());
    if (k % every == 0 || k == steps) output();
    if (o.log) {
      std::ostringstream detail;
      detail << model.elements().size() << " elements, t = " << std::lround(model.time()) << " s";
      progress.update(k, detail.str());
    }
  }
  if (o.log) progress.finish(std::to_string(model.elements().size()) + " elements");

  // A Ctrl-C while the outputs are written keeps the contract too: exit 130, nothing written.
  const auto check_stop = [&] {
    if (o.stop && o.stop->load())
      throw common::Interrupted("forecast interrupted; nothing written");
  };
  check_stop();
  write_budget(dir, outputs);
  check_stop();
  write_slick_geojson((dir / "slick.geojson").string(), slicks, flow.grid(), flow.crs_wkt());
  write_shoreline_geojson((dir / "shoreline.geojson").string(), shores, model.setup().centreline,
                          model.setup().banks, flow.crs_wkt());
  check_stop();
  NetcdfAttributes attributes;
  attributes.title = config.name;
  attributes.summary = config.description;
  attributes.start_iso = config.start_date;
  attributes.oil_name = setup.model.oil.name;
  attributes.oil_source = setup.model.oil.source;
  attributes.crs_wkt = flow.crs_wkt();
  attributes.history = "spill-sim forecast --config " + o.config_file;
  write_trajectory_netcdf((dir / "elements.nc").string(), snapshots, attributes);
  check_stop();

  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  nlohmann::json watch = nlohmann::json::array();
  for (const WatchPoint& p : points)
    watch.push_back(
        {{"name", p.name},
         {"km", p.km / 1000},
         {"position", {p.x, p.y}},
         {"radius_m", p.radius},
         {"arrival_s", p.arrival_s >= 0 ? nlohmann::json(p.arrival_s) : nlohmann::json()},
         {"arrival_time",
          p.arrival_s >= 0 ? nlohmann::json(utc_text(start + std::time_t(std::lround(p.arrival_s))))
                           : nlohmann::json()}});
  nlohmann::json oil_components = nlohmann::json::array();
  for (const auto& p : setup.model.oil.components)
    oil_components.push_back({{"boiling_point_k", p.volatile_cut ? nlohmann::json(p.boiling_point_k)
                                                                 : nlohmann::json("residue")},
                              {"mass_fraction", p.mass_fraction},
                              {"molecular_weight_kg_mol", p.molecular_weight},
                              {"density_kg_m3", p.density}});
  const Budget b = model.budget();
  nlohmann::json summary = {
      {"name", config.name},
      {"description", config.description},
      {"config", common::JsonWriter::write_struct(config)},
      {"oil",
       {{"name", setup.model.oil.name},
        {"source", setup.model.oil.source},
        {"file", setup.model.oil.file},
        {"emulsification_onset", setup.model.oil.emulsification_onset},
        {"pseudo_components", oil_components}}},
      {"reach_run", config.flow.reach_run},
      {"start_date", config.start_date},
      {"end_time_s", model.time()},
      {"steps", model.steps()},
      {"elements", model.elements().size()},
      {"budget_closure_worst", worst_closure},
      {"released_m3", b.released / setup.model.oil.density},
      {"watch_points", watch},
      {"handover", o.handover.empty()
                       ? nlohmann::json()
                       : nlohmann::json{{"near_field", o.handover_summary},
                                        {"parcels", o.handover.size()},
                                        {"volume_m3", handed_over_m3},
                                        {"mass_kg", handed_over_m3 * setup.model.oil.density}}},
      {"outputs", outputs},
      {"wall_s", wall},
      {"threads", o.threads},
      {"definitions",
       {{"oiled_area_m2",
         "the reach's cells the floating oil covers: each element's area added to "
         "its cell, a cell counted at most once"},
        {"leading_edge_km",
         "the farthest oil (floating or stranded) along the centreline, km "
         "from its first point"},
        {"banks",
         "left and right looking downstream; oiled_length_km: the bank bins holding "
         "stranded oil; per_km: stranded emulsion volume per whole km"},
        {"budget_kg",
         "oil mass (water not counted): released = floating + stranded + "
         "evaporated + dispersed + left_reach; closure_error is relative"},
        {"watch_points",
         "arrival_s: the first step's end at which oil (floating or stranded) "
         "lay within the radius; null: not reached"}}}};
  std::ofstream((dir / "forecast.json")) << summary.dump(2) << "\n";
  check_stop();
  folder.commit();
  return summary;
}

}  // namespace farfield
