#include "farfield/forecast_recorder.h"

#include <cmath>
#include <cstdio>
#include <fstream>

#include "common/config_visitors.h"
#include "common/exit_codes.h"
#include "common/image_writer.h"
#include "common/svg_plot.h"
#include "farfield/outputs/forecast_map.h"

namespace farfield {

namespace fs = std::filesystem;

namespace {

std::string utc_text(std::time_t t) {
  std::tm tm{};
  gmtime_r(&t, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return text;
}

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
         "sunk_kg,closure_error\n";
  csv.precision(12);
  std::vector<common::PlotSeries> series = {{"floating", {}, {}},       {"stranded", {}, {}},
                                            {"evaporated", {}, {}},     {"dispersed", {}, {}},
                                            {"left the reach", {}, {}}, {"sunk", {}, {}}};
  const char* keys[] = {"floating", "stranded", "evaporated", "dispersed", "left_reach", "sunk"};
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

nlohmann::json oil_json(const OilRecord& oil) {
  nlohmann::json components = nlohmann::json::array();
  for (const auto& p : oil.components)
    components.push_back({{"boiling_point_k", p.volatile_cut ? nlohmann::json(p.boiling_point_k)
                                                             : nlohmann::json("residue")},
                          {"mass_fraction", p.mass_fraction},
                          {"molecular_weight_kg_mol", p.molecular_weight},
                          {"density_kg_m3", p.density}});
  return {{"name", oil.name},
          {"source", oil.source},
          {"file", oil.file},
          {"emulsification_onset", oil.emulsification_onset},
          {"max_water_fraction", oil.max_water_fraction},
          {"max_water_fraction_source", oil.max_water_source},
          {"fingas_evaporation",
           {{"a", oil.fingas.a},
            {"b", oil.fingas.b},
            {"form", oil.fingas.square_root ? "sqrt" : "ln"},
            {"source", oil.fingas.source}}},
          {"pseudo_components", components}};
}

// forecast.json's words for its figures, so that a reader of the file alone can use them.
nlohmann::json definitions_json() {
  return {{"oiled_area_m2",
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
           "evaporated + dispersed + left_reach + sunk; closure_error is relative"},
          {"watch_points",
           "arrival_s: the first step's end at which oil (floating or stranded) "
           "lay within the radius; null: not reached"}};
}

}  // namespace

ForecastRecorder::ForecastRecorder(fs::path dir, const ForecastSetup& setup, const ReachFlow& flow,
                                   bool pictures, const std::atomic<bool>* stop)
    : dir_(std::move(dir)),
      setup_(setup),
      flow_(flow),
      pictures_(pictures),
      stop_(stop),
      lon_lat_(flow.crs_wkt()) {
  if (pictures_) fs::create_directories(dir_ / "png");
  map_colour_scales(flow_, depth_scale_, speed_scale_);
}

void ForecastRecorder::check_stop() const {
  if (stop_ && stop_->load()) throw common::Interrupted("forecast interrupted; nothing written");
}

std::string ForecastRecorder::clock(double t_s) const {
  return utc_text(setup_.start_epoch + std::time_t(std::lround(t_s)));
}

void ForecastRecorder::record(const FarFieldModel& model, const std::vector<WatchPoint>& points) {
  const double t = model.time();
  nlohmann::json record = forecast_record(model, flow_.grid(), points);
  record["time"] = clock(t);
  outputs_.push_back(record);
  slicks_.push_back(
      {t, record["time"], oiled_cells(model, flow_.grid()), oiled_volume(model, flow_.grid())});
  ShoreSnapshot shore = shore_snapshot(model);
  shore.clock = record["time"];
  shores_.push_back(std::move(shore));
  const WeatherNow w = setup_.model.environment.weather_at(t);
  elements_.push_back(element_snapshot(model, lon_lat_, w.water_temperature_c, w.water_density));
  check_stop();
  if (pictures_) {
    char name[64];
    std::snprintf(name, sizeof name, "png/map_%05zu.png", outputs_.size() - 1);
    outputs_.back()["map"] = name;
    common::write_png((dir_ / name).string(),
                      draw_forecast_map(flow_, model, points, depth_scale_, speed_scale_));
  }
}

std::vector<double> ForecastRecorder::output_times() const {
  std::vector<double> t;
  for (const SlickSnapshot& s : slicks_) t.push_back(s.t_s);
  return t;
}

std::vector<std::string> ForecastRecorder::output_clocks() const {
  std::vector<std::string> c;
  for (const SlickSnapshot& s : slicks_) c.push_back(s.clock);
  return c;
}

nlohmann::json ForecastRecorder::finish(const FarFieldModel& model,
                                        const std::vector<WatchPoint>& points,
                                        const ForecastRunFacts& facts) {
  // A Ctrl-C while the outputs are written keeps the contract too: exit 130, nothing written.
  check_stop();
  write_budget(dir_, outputs_);
  check_stop();
  write_slick_geojson((dir_ / "slick.geojson").string(), slicks_, flow_.grid(), flow_.crs_wkt());
  write_shoreline_geojson((dir_ / "shoreline.geojson").string(), shores_, model.setup().centreline,
                          model.setup().banks, flow_.crs_wkt(), facts.shore_probability);
  check_stop();
  const ForecastConfig& config = setup_.config;
  NetcdfAttributes attributes;
  attributes.title = config.name;
  attributes.summary = config.description;
  attributes.start_iso = config.start_date;
  attributes.oil_name = setup_.model.oil.name;
  attributes.oil_source = setup_.model.oil.source;
  attributes.crs_wkt = flow_.crs_wkt();
  attributes.history = "spill-sim forecast --config " + facts.config_file;
  write_trajectory_netcdf((dir_ / "elements.nc").string(), elements_, attributes);
  check_stop();
  const nlohmann::json content = summary(model, points, facts);
  std::ofstream((dir_ / "forecast.json")) << content.dump(2) << "\n";
  check_stop();
  return content;
}

nlohmann::json ForecastRecorder::summary(const FarFieldModel& model,
                                         const std::vector<WatchPoint>& points,
                                         const ForecastRunFacts& facts) const {
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - facts.wall_start).count();
  const auto or_null = [](bool known, const nlohmann::json& value) {
    return known ? value : nlohmann::json();
  };
  nlohmann::json watch = nlohmann::json::array();
  for (const WatchPoint& p : points) {
    const bool arrived = p.arrival_s >= 0;
    watch.push_back({{"name", p.name},
                     {"km", p.km / 1000},
                     {"position", {p.x, p.y}},
                     {"radius_m", p.radius},
                     {"arrival_s", or_null(arrived, p.arrival_s)},
                     {"arrival_time", or_null(arrived, arrived ? clock(p.arrival_s) : "")}});
  }
  const ForecastConfig& config = setup_.config;
  const double oil_density = setup_.model.oil.density;
  const nlohmann::json handover =
      facts.handover_parcels == 0 ? nlohmann::json()
                                  : nlohmann::json{{"near_field", facts.handover_summary},
                                                   {"parcels", facts.handover_parcels},
                                                   {"volume_m3", facts.handed_over_m3},
                                                   {"mass_kg", facts.handed_over_m3 * oil_density}};
  return {{"name", config.name},
          {"description", config.description},
          {"config", common::JsonWriter::write_struct(config)},
          {"oil", oil_json(setup_.model.oil)},
          {"reach_run", config.flow.reach_run},
          {"start_date", config.start_date},
          {"end_time_s", model.time()},
          {"steps", model.steps()},
          {"elements", model.elements().size()},
          {"budget_closure_worst", facts.worst_closure},
          {"released_m3", model.budget().released / oil_density},
          {"watch_points", watch},
          {"handover", handover},
          {"ensemble", facts.ensemble},
          {"outputs", outputs_},
          {"wall_s", wall},
          {"threads", facts.threads},
          {"definitions", definitions_json()}};
}

}  // namespace farfield
