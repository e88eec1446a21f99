// A far-field forecast from its config (farfield/forecast_run.h) on a straight channel's reach
// run made here: every output is written and readable by the tools a responder uses (GDAL's
// ogrinfo for the RFC 7946 GeoJSON, ncdump for the CF NetCDF), the budget closes at every
// output, and bad input is refused naming the file and the key with nothing written.

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include "common/checked_file.h"
#include "common/config_error.h"
#include "common/exit_codes.h"
#include "common/json_file.h"
#include "farfield/flows/reach_flow.h"
#include "farfield/forecast_run.h"
#include "reach/raster.h"
#include "reach/reach_run.h"

namespace fs = std::filesystem;

namespace {

std::string shell(const std::string& command, int& status) {
  std::string out;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return out;
  std::array<char, 4096> buffer{};
  while (fgets(buffer.data(), int(buffer.size()), pipe)) out += buffer.data();
  status = pclose(pipe);
  return out;
}

class Forecast : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("spill_forecast_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    // A channel 1 km long, its flat bed 60 m wide falling 1 in 1000 to the west between banks
    // 2 m high, on 10 m cells in NZTM2000 coordinates; 12 m^3/s run to a steady state.
    reach::Raster r;
    r.grid.nx = 100, r.grid.ny = 8, r.grid.dx = r.grid.dy = 10;
    r.grid.x0 = 1771000, r.grid.y0 = 5472000;
    for (int j = 0; j < r.grid.ny; ++j)
      for (int i = 0; i < r.grid.nx; ++i)
        r.values.push_back(0.001 * r.grid.x(i) - 1771.0 + ((j == 0 || j == 7) ? 2.0 : 0.0));
    r.crs_wkt = reach::crs_wkt_of("EPSG:2193");
    reach::write_geotiff((dir_ / "channel.tif").string(), r);
    const nlohmann::json reach_config = {
        {"terrain", {{"file", "channel.tif"}, {"manning", 0.03}}},
        {"inflows",
         {{{"section", {{"name", "up"}, {"side", "east"}, {"from", 5472010}, {"to", 5472070}}},
           {"discharge", {{"value", 12.0}}}}}},
        {"outflows",
         {{{"section", {{"name", "down"}, {"side", "west"}, {"from", 5472010}, {"to", 5472070}}},
           {"kind", "normal_depth"},
           {"slope", 0.001}}}},
        {"end_time", 7200},
        {"output_every", 1800},
        {"steady_tolerance", 1e-5}};
    std::ofstream(dir_ / "reach.json") << reach_config.dump(2);
    reach::ReachRunOptions o;
    o.config_file = (dir_ / "reach.json").string();
    o.out_dir = (dir_ / "reach_run").string();
    std::ostringstream log;
    o.log = &log;
    reach::run_reach(o);
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }

  static nlohmann::json config() {
    return {{"name", "channel spill"},
            {"flow", {{"reach_run", "reach_run"}}},
            {"centreline", {{1771995, 5472040}, {1771005, 5472040}}},
            {"oil", "light_crude"},
            {"releases",
             {{{"position", {1771900, 5472040}},
               {"start", 0},
               {"end", 300},
               {"rate", {{"value", 0.01}}},
               {"elements", 600}}}},
            {"environment",
             {{"water_temperature", {{"value", 12}}},
              {"wind_speed", {{"points", {{0, 3}, {1200, 6}}}}},
              {"wind_from", {{"value", 100}}}}},
            {"banks",
             {{"bin_length", 50},
              {"classes", {{{"name", "grass"}, {"capacity", 0.005}, {"refloat_half_life", 2}}}},
              {"default_class", "grass"}}},
            {"watch_points", {{{"name", "intake"}, {"position", {1771300, 5472040}}}}},
            {"end_time", 1200},
            {"time_step", 30},
            {"output_every", 300},
            {"start_date", "2026-06-01T06:00:00Z"}};
  }
  static nlohmann::json run(const nlohmann::json& c, const std::string& out,
                            const std::vector<std::string>& overrides = {}) {
    std::ofstream(dir_ / "forecast.json") << c.dump(2);
    farfield::ForecastRunOptions o;
    o.config_file = (dir_ / "forecast.json").string();
    o.overrides = overrides;
    o.out_dir = (dir_ / out).string();
    return farfield::run_forecast(o);
  }
  // The message of the input error a run throws ("" when none), checking nothing was written.
  static std::string refusal(const std::vector<std::string>& overrides) {
    try {
      run(config(), "refused", overrides);
    } catch (const common::InputError& e) {
      EXPECT_FALSE(fs::exists(dir_ / "refused")) << "a refused forecast wrote its folder";
      return e.what();
    }
    return "";
  }
  static fs::path dir_;
};
fs::path Forecast::dir_;

// The rows of report.html's table `id` (its header row not counted; -1 when there is no such
// table).
int table_rows(const std::string& html, const std::string& id) {
  const size_t start = html.find("<table id=\"" + id + "\">");
  if (start == std::string::npos) return -1;
  const size_t end = html.find("</table>", start);
  int rows = -1;
  for (size_t at = html.find("<tr>", start); at < end; at = html.find("<tr>", at + 1)) ++rows;
  return rows;
}

}  // namespace

TEST_F(Forecast, WritesEveryOutputThatItsToolsRead) {
  const nlohmann::json summary = run(config(), "out");
  const fs::path out = dir_ / "out";
  for (const char* f : {"forecast.json", "budget.csv", "budget.svg", "slick.geojson",
                        "shoreline.geojson", "elements.nc", "png/map_00000.png", "report.html"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  // Released as configured: 0.01 m^3/s for 300 s.
  EXPECT_NEAR(summary["released_m3"].get<double>(), 3.0, 1e-9);
  ASSERT_EQ(summary["outputs"].size(), 5u);
  for (const auto& o : summary["outputs"])
    EXPECT_LT(o["budget_kg"]["closure_error"].get<double>(), 1e-9);
  EXPECT_LT(summary["budget_closure_worst"].get<double>(), 1e-9);
  const auto& last = summary["outputs"].back();
  EXPECT_GT(last["oiled_area_m2"].get<double>(), 0);
  EXPECT_GT(last["leading_edge_km"].get<double>(), 0.1);  // it left the release point
  EXPECT_GT(last["budget_fraction"]["evaporated"].get<double>(), 0);
  // The intake 600 m downstream of the release is reached (the surface moves at about 0.4 m/s).
  EXPECT_TRUE(summary["watch_points"][0]["arrival_s"].is_number());
  EXPECT_NEAR(summary["watch_points"][0]["km"].get<double>(), 0.695, 1e-6);
  // report.html: the budget at every output time, the intake's first oil as forecast.json has
  // it (in hours and minutes after the start), the maps behind a slider.
  const std::string report = common::read_whole_file(out / "report.html");
  EXPECT_EQ(table_rows(report, "budget"), int(summary["outputs"].size()));
  EXPECT_EQ(table_rows(report, "watch-points"), 1);
  const long minutes = std::lround(summary["watch_points"][0]["arrival_s"].get<double>() / 60);
  char arrival[32];
  std::snprintf(arrival, sizeof arrival, "%ld h %02ld min", minutes / 60, minutes % 60);
  EXPECT_NE(report.find(arrival), std::string::npos) << arrival;
  EXPECT_NE(report.find("map-slider"), std::string::npos);
  EXPECT_EQ(table_rows(report, "arrival-quantiles"), -1) << "no ensemble, no ensemble table";

  int status = -1;
  const std::string info =
      shell("ogrinfo -so " + (out / "slick.geojson").string() + " slick", status);
  EXPECT_EQ(status, 0) << info;
  EXPECT_NE(info.find("GeoJSON"), std::string::npos) << info;
  EXPECT_NE(info.find("WGS 84"), std::string::npos) << info;
  const std::string shore =
      shell("ogrinfo -so " + (out / "shoreline.geojson").string() + " stranded_shoreline", status);
  EXPECT_EQ(status, 0) << shore;
  const std::string header = shell("ncdump -h " + (out / "elements.nc").string(), status);
  EXPECT_EQ(status, 0) << header;
  for (const char* attribute :
       {":featureType = \"trajectory\"", ":Conventions = \"CF-1.6\"", "cf_role = \"trajectory_id\"",
        "lon:units = \"degrees_east\"", "lat:standard_name = \"latitude\"", "status:flag_meanings"})
    EXPECT_NE(header.find(attribute), std::string::npos) << attribute << "\n" << header;

  // RFC 7946: lon/lat in NZ (east of 166 deg, south of -34 deg), exterior rings counter-clockwise.
  const nlohmann::json slick = common::load_json_file((out / "slick.geojson").string(), "slick");
  ASSERT_FALSE(slick["features"].empty());
  for (const auto& f : slick["features"]) {
    const auto& ring = f["geometry"]["coordinates"][0];
    double twice_area = 0;
    for (size_t k = 0; k + 1 < ring.size(); ++k) {
      EXPECT_GT(ring[k][0].get<double>(), 166);
      EXPECT_LT(ring[k][1].get<double>(), -34);
      twice_area += ring[k][0].get<double>() * ring[k + 1][1].get<double>() -
                    ring[k + 1][0].get<double>() * ring[k][1].get<double>();
    }
    EXPECT_GT(twice_area, 0) << "an exterior ring runs clockwise";
    // Each polygon is one Bonn Agreement appearance class, its thickness range with it.
    const auto& p = f["properties"];
    const int code = p["bonn_code"].get<int>();
    EXPECT_GE(code, 1);
    EXPECT_LE(code, 5);
    EXPECT_FALSE(p["appearance"].get<std::string>().empty());
    if (code < 5) {
      EXPECT_LT(p["thickness_um_from"].get<double>(), p["thickness_um_to"].get<double>());
    }
  }
}

// The emulsion's water limit: the record's (light crude: none measured, so adios_db's estimate)
// unless the config sets it, and forecast.json says which.
TEST_F(Forecast, TheOilsWaterLimitAndItsSourceAreReported) {
  const nlohmann::json estimated = run(config(), "water_estimated");
  EXPECT_EQ(estimated["oil"]["max_water_fraction"].get<double>(), 0.9);
  EXPECT_NE(estimated["oil"]["max_water_fraction_source"].get<std::string>().find("adios_db"),
            std::string::npos);
  const nlohmann::json set = run(config(), "water_set", {"/oil/max_water_content=0.5"});
  EXPECT_EQ(set["oil"]["max_water_fraction"].get<double>(), 0.5);
  EXPECT_NE(
      set["oil"]["max_water_fraction_source"].get<std::string>().find("/oil/max_water_content"),
      std::string::npos);
  // The object form names the oil as the plain name does.
  nlohmann::json c = config();
  c["oil"] = {{"name", "light_crude"}, {"max_water_content", 0.5}};
  const nlohmann::json object = run(c, "water_object");
  EXPECT_EQ(object["oil"]["max_water_fraction"].get<double>(), 0.5);
  EXPECT_EQ(object["released_m3"], set["released_m3"]);
}

TEST_F(Forecast, BadInputIsRefusedNamingTheFileAndKey) {
  const auto names = [](const std::string& message, const std::string& key) {
    return message.find("forecast.json") != std::string::npos &&
           message.find(key) != std::string::npos;
  };
  std::string m = refusal({"/oil=\"whale oil\""});
  EXPECT_TRUE(names(m, "/oil")) << m;
  EXPECT_NE(m.find("medium_crude"), std::string::npos) << m;  // the library is listed
  m = refusal({"/releases/0/rate/value=-0.01"});
  EXPECT_TRUE(names(m, "/releases/0/rate")) << m;
  m = refusal({"/watch_points/0/position=[1790000, 5472040]"});
  EXPECT_TRUE(names(m, "/watch_points/0/position")) << m;
  EXPECT_NE(m.find("outside the reach"), std::string::npos) << m;
  m = refusal({"/environment/wind_speed/points=[[0, 3], [600, 6]]"});
  EXPECT_TRUE(names(m, "/environment/wind_speed")) << m;
  EXPECT_NE(m.find("extend it"), std::string::npos) << m;
  m = refusal({"/banks/default_class=\"rock\""});
  EXPECT_TRUE(names(m, "/banks/default_class")) << m;
  m = refusal({"/releases/0/position=[1771500, 5472005]"});  // on the dry bank top
  EXPECT_TRUE(names(m, "/releases/0/position")) << m;
  m = refusal({"/flow/reach_run=\"nowhere\""});
  EXPECT_TRUE(names(m, "/flow/reach_run")) << m;
  // A near field is a scene to run or a finished run's folder: one of the two.
  m = refusal({"/near_field={\"scene\": \"a.json\", \"run\": \"b\"}"});
  EXPECT_TRUE(names(m, "/near_field/run")) << m;
  m = refusal({"/near_field={\"elements_per_parcel\": 3}"});
  EXPECT_TRUE(names(m, "/near_field/scene")) << m;
  m = refusal({"/near_field={\"run\": \"b\", \"set\": [\"/end_time=3\"]}"});
  EXPECT_TRUE(names(m, "/near_field/set")) << m;
}

// docs/far_field_reference.md is `spill-sim forecast-doc`'s output: regenerate it when a key
// changes (spill-sim forecast-doc > docs/far_field_reference.md).
TEST(ForecastConfig, TheReferenceDocumentsEveryKey) {
  std::ifstream in(std::string(SPILL_SOURCE_DIR) + "/docs/far_field_reference.md");
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_NE(text.str().find(farfield::forecast_reference_markdown()), std::string::npos)
      << "regenerate docs/far_field_reference.md with spill-sim forecast-doc";
}

// Every shipped forecast loads, and builds on its reach run, or names the run it needs.
TEST(ForecastConfig, EveryShippedConfigBuildsOrNamesItsReachRun) {
  for (const auto& entry :
       fs::directory_iterator(std::string(SPILL_SOURCE_DIR) + "/configs/far_field")) {
    const std::string file = entry.path().string();
    const farfield::ForecastConfig c = farfield::load_forecast_config(file, {});
    try {
      const farfield::ForecastSetup s = farfield::build_forecast(c, file);
      EXPECT_TRUE(!s.model.releases.empty() || s.config.near_field) << file;
    } catch (const common::ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("/flow/reach_run"), std::string::npos) << e.what();
      EXPECT_FALSE(fs::exists(c.flow.reach_run + "/reach.json")) << e.what();
    }
  }
}

// With a near field, spill-sim forecast checks the far field's own input before it spends
// minutes on the near field's SPH: a bad oil is refused at once (exit 2, naming the key).
TEST(ForecastCommand, ANearFieldForecastRefusesBadInputBeforeTheNearField) {
  const std::string config =
      std::string(SPILL_SOURCE_DIR) + "/configs/far_field/white_river_leak_forecast.json";
  const std::string out =
      (fs::temp_directory_path() / ("spill_forecast_cli_" + std::to_string(getpid()))).string();
  int status = -1;
  const std::string said = shell(std::string(SPILL_SIM_EXE) + " forecast --config " + config +
                                     " --set /oil=whale_oil --out " + out,
                                 status);
  EXPECT_EQ(WEXITSTATUS(status), 2) << said;
  EXPECT_NE(said.find("/oil"), std::string::npos) << said;
  EXPECT_EQ(said.find("near field"), std::string::npos) << "the near field ran first:\n" << said;
  EXPECT_FALSE(fs::exists(out));
}

// Input that is wrong but would run and look right is refused before any work, naming the key.
TEST_F(Forecast, PlausibleButWrongInputIsRefusedBeforeAnyWork) {
  const auto names = [](const std::string& message, const std::string& key) {
    return message.find("forecast.json:" + key + ":") != std::string::npos;
  };
  // Water at 293 "degrees": kelvin by mistake (it evaporated 80 % instead of 19 %).
  std::string m = refusal({"/environment/water_temperature/value=293"});
  EXPECT_TRUE(names(m, "/environment/water_temperature")) << m;
  EXPECT_NE(m.find("reads as kelvin"), std::string::npos) << m;
  // A centreline far from the reach (a leading edge of 3,889 km), or beside it on the bank.
  m = refusal({"/centreline=[[1771995, 9472040], [1771005, 9472040]]"});
  EXPECT_TRUE(names(m, "/centreline/0")) << m;
  m = refusal({"/centreline=[[1771995, 5472004], [1771005, 5472004]]"});
  EXPECT_TRUE(names(m, "/centreline")) << m;
  EXPECT_NE(m.find("% of its"), std::string::npos) << m;
  // Work that would not end: steps, the drift's sub-steps, a run for ever on a steady reach.
  m = refusal({"/time_step=1e-6", "/output_every=300"});
  EXPECT_TRUE(names(m, "/time_step")) << m;
  m = refusal({"/drift/max_cells_per_substep=1e-9"});
  EXPECT_TRUE(names(m, "/drift/max_cells_per_substep")) << m;
  m = refusal({"/end_time=1e12", "/environment/wind_speed={\"value\": 3}"});
  EXPECT_TRUE(names(m, "/end_time")) << m;
  EXPECT_NE(m.find("/max_steps"), std::string::npos) << m;
  // Memory that is not there: two billion elements, bank bins of a micrometre.
  m = refusal({"/releases/0/elements=2000000000"});
  EXPECT_TRUE(names(m, "/releases")) << m;
  EXPECT_NE(m.find("GB"), std::string::npos) << m;
  m = refusal({"/banks/bin_length=1e-6"});
  EXPECT_TRUE(names(m, "/banks/bin_length")) << m;
  // Values that ran to the end and failed there, naming the staging folder or PROJ: bins
  // longer than the centreline are drawn along it, Manning's n over 1 is refused.
  run(config(), "long_bins", {"/banks/bin_length=1e9"});
  const nlohmann::json shore =
      common::load_json_file((dir_ / "long_bins" / "shoreline.geojson").string(), "shoreline");
  ASSERT_FALSE(shore["features"].empty()) << "no oil stranded";
  for (const auto& f : shore["features"]) {
    EXPECT_LE(f["properties"]["km_to"].get<double>(), 0.99);  // the centreline's 990 m
    for (const auto& p : f["geometry"]["coordinates"]) {
      EXPECT_NEAR(p[0].get<double>(), 175.5, 1) << p;  // NZTM 1771000 E, 5472000 N
      EXPECT_NEAR(p[1].get<double>(), -40.9, 1) << p;
    }
  }
  m = refusal({"/flow/manning=1e9"});
  EXPECT_TRUE(names(m, "/flow/manning")) << m;
}

// The ensemble (issue 49): member 0 is the forecast itself, so the deterministic outputs do not
// change when an ensemble runs beside them; the members are reproducible by their seed; the
// files a responder reads are there and read by GDAL.
TEST_F(Forecast, AnEnsembleLeavesItsForecastAsItWasAndIsReproducible) {
  const std::vector<std::string> ensemble = {"/ensemble={\"members\": 6, \"seed\": 3}"};
  const nlohmann::json alone = run(config(), "deterministic");
  const nlohmann::json with = run(config(), "ensemble_a", ensemble);
  EXPECT_EQ(with["outputs"], alone["outputs"]);
  EXPECT_EQ(with["watch_points"], alone["watch_points"]);
  EXPECT_TRUE(alone["ensemble"].is_null());
  const nlohmann::json& e = with["ensemble"];
  ASSERT_EQ(e["members"].get<int>(), 6);
  EXPECT_EQ(e["draws"][0]["wind_speed_factor"].get<double>(), 1.0);  // member 0: unperturbed
  EXPECT_NE(e["draws"][1]["wind_speed_factor"].get<double>(), 1.0);
  // The same seed gives the same members; another seed others.
  const nlohmann::json again = run(config(), "ensemble_b", ensemble);
  EXPECT_EQ(again["ensemble"], e);
  const nlohmann::json other =
      run(config(), "ensemble_c", {"/ensemble={\"members\": 6, \"seed\": 4}"});
  EXPECT_NE(other["ensemble"]["draws"], e["draws"]);

  // Arrival quantiles in order, and the probability of arrival never falls.
  const nlohmann::json& intake = e["watch_points"][0];
  const auto& q = intake["arrival_s_quantiles"];
  ASSERT_TRUE(q["p10"].is_number()) << q;
  if (q["p90"].is_number()) {
    EXPECT_LE(q["p10"].get<double>(), q["p50"].get<double>());
    EXPECT_LE(q["p50"].get<double>(), q["p90"].get<double>());
  }
  double last = 0;
  for (const auto& p : intake["arrival_probability"]) {
    EXPECT_GE(p["probability"].get<double>(), last);
    last = p["probability"].get<double>();
  }
  EXPECT_GT(last, 0);

  const fs::path out = dir_ / "ensemble_a";
  EXPECT_TRUE(fs::exists(out / "png/probability.png"));
  int status = -1;
  const std::string info = shell("gdalinfo " + (out / "probability.tif").string(), status);
  EXPECT_EQ(status, 0) << info;
  EXPECT_NE(info.find("Band 5 "), std::string::npos) << "a band per output time:\n" << info;
  EXPECT_NE(info.find("probability of oiling by"), std::string::npos) << info;
  EXPECT_NE(info.find("NZGD2000"), std::string::npos) << "not in the reach's CRS:\n" << info;
  const nlohmann::json shore =
      common::load_json_file((out / "shoreline.geojson").string(), "shoreline");
  bool probability_line = false;
  for (const auto& f : shore["features"])
    if (f["properties"]["kind"] == "probability") {
      probability_line = true;
      EXPECT_GT(f["properties"]["oiling_probability"].get<double>(), 0);
      EXPECT_LE(f["properties"]["oiling_probability"].get<double>(), 1);
    }
  EXPECT_TRUE(probability_line);
  // Per whole kilometre of a bank: at least the largest share of any of its bins.
  for (const auto& km : e["bank_km_oiling_probability"]) {
    double most = 0;
    for (const auto& bin : e["bank_oiling_probability"])
      if (bin["bank"] == km["bank"] &&
          bin["km_from"].get<double>() >= km["km_from"].get<double>() &&
          bin["km_from"].get<double>() < km["km_to"].get<double>())
        most = std::max(most, bin["probability"].get<double>());
    EXPECT_GE(km["probability"].get<double>(), most - 1e-12) << km;
    EXPECT_GT(km["probability"].get<double>(), 0) << km;
    // shoreline.geojson draws the same kilometre with the same share.
    int drawn = 0;
    for (const auto& f : shore["features"]) {
      const auto& p = f["properties"];
      if (p["kind"] != "probability_km" || p["bank"] != km["bank"] ||
          std::floor(p["km_from"].get<double>() + 1e-9) != km["km_from"].get<double>())
        continue;
      ++drawn;
      EXPECT_EQ(p["oiling_probability"].get<double>(), km["probability"].get<double>()) << km;
    }
    EXPECT_EQ(drawn, 1) << km;
  }
  EXPECT_FALSE(e["bank_km_oiling_probability"].empty());
  // report.html's ensemble tables: a row per watch point, per oiled bank kilometre, per budget
  // part; the probability picture.
  const std::string report = common::read_whole_file(out / "report.html");
  EXPECT_EQ(table_rows(report, "arrival-quantiles"), int(e["watch_points"].size()));
  EXPECT_EQ(table_rows(report, "bank-km-probability"), int(e["bank_km_oiling_probability"].size()));
  EXPECT_EQ(table_rows(report, "budget-quantiles"), 6);
  EXPECT_NE(report.find("members whose oil had been in each cell"), std::string::npos);

  // Bad ensemble input is refused naming its key.
  std::string m = refusal({"/ensemble={\"members\": 1}"});
  EXPECT_NE(m.find("/ensemble/members"), std::string::npos) << m;
  m = refusal({"/ensemble={\"oils\": [\"whale_oil\"]}"});
  EXPECT_NE(m.find("/ensemble/oils/0"), std::string::npos) << m;
  // Members that would not end: each does the forecast's work again.
  m = refusal({"/ensemble={\"members\": 10000}", "/max_steps=100000"});
  EXPECT_NE(m.find("/ensemble/members"), std::string::npos) << m;
  EXPECT_NE(m.find("/max_steps"), std::string::npos) << m;
}

// An ensemble over a job array: three shards of its members, each into its own file, then a run
// that takes the members from their files gives the ensemble a single process gives; a missing
// shard or a shard of another config is refused, naming it.
TEST_F(Forecast, AnEnsembleRunAsShardsIsTheEnsembleOfOneProcess) {
  const std::vector<std::string> ensemble = {"/ensemble={\"members\": 7, \"seed\": 5}"};
  const nlohmann::json one = run(config(), "one_process", ensemble);
  const auto options = [&](const std::string& out) {
    farfield::ForecastRunOptions o;
    o.config_file = (dir_ / "forecast.json").string();
    o.overrides = ensemble;
    o.out_dir = (dir_ / out).string();
    return o;
  };
  for (int i = 0; i < 3; ++i) {
    farfield::ForecastRunOptions o = options("shards");
    o.shard = common::ArrayTask{i, 3};
    const nlohmann::json shard = farfield::run_forecast(o);
    EXPECT_EQ(shard["members_run"].size(), 2u);  // members 1-6, two each
  }
  EXPECT_FALSE(fs::exists(dir_ / "shards" / "forecast.json"));  // a shard writes only its file
  farfield::ForecastRunOptions assemble = options("assembled");
  assemble.members_from = (dir_ / "shards").string();
  const nlohmann::json assembled = farfield::run_forecast(assemble);
  EXPECT_EQ(assembled["ensemble"], one["ensemble"]);
  EXPECT_EQ(assembled["outputs"], one["outputs"]);

  // Shard 2 of 3 missing: its members are named, nothing is written.
  fs::rename(dir_ / "shards" / "ensemble_shard_2_of_3.json", dir_ / "shard_2.json");
  assemble.out_dir = (dir_ / "refused_assembly").string();
  try {
    farfield::run_forecast(assemble);
    ADD_FAILURE() << "an assembly with a shard missing ran";
  } catch (const common::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("2 members no shard ran (3, 6)"), std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(fs::exists(dir_ / "refused_assembly"));
  // A shard of another ensemble seed: another config.
  farfield::ForecastRunOptions other = options("shards");
  other.overrides = {"/ensemble={\"members\": 7, \"seed\": 6}"};
  other.shard = common::ArrayTask{2, 3};
  farfield::run_forecast(other);
  try {
    farfield::run_forecast(assemble);
    ADD_FAILURE() << "a shard of another config was taken";
  } catch (const common::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("ensemble_shard_2_of_3.json: a shard of another config"),
              std::string::npos)
        << e.what();
  }
}

// A symmetric case: a straight channel symmetric about its centreline, the release on it, a wind
// along it whose direction the members turn either way alike. The probability of oiling is then
// symmetric about the centreline, within the sampling noise of 100 members.
TEST_F(Forecast, ASymmetricCaseGivesASymmetricProbabilityMap) {
  nlohmann::json c = config();
  c["environment"]["wind_speed"] = {{"value", 4}};
  c["environment"]["wind_from"] = {{"value", 90}};  // from the east: straight downstream
  c["ensemble"] = {{"members", 100},  {"seed", 11},      {"wind_direction", 30},
                   {"wind_speed", 0}, {"flow_speed", 0}, {"volume", 0}};
  const nlohmann::json summary = run(c, "symmetric");
  // The last band (by the end), taken out by GDAL: the channel's south half against its north.
  const fs::path folder = dir_ / "symmetric";
  int status = -1;
  const std::string said = shell("gdal_translate -q -b 5 " + (folder / "probability.tif").string() +
                                     " " + (folder / "last.tif").string(),
                                 status);
  ASSERT_EQ(status, 0) << said;
  const reach::Raster p = reach::read_raster((folder / "last.tif").string());
  ASSERT_EQ(p.grid.ny, 8);
  double south = 0, north = 0;
  for (int j = 0; j < p.grid.ny; ++j)
    for (int i = 0; i < p.grid.nx; ++i) {
      const double v = p.values[p.grid.at(i, j)];
      if (std::isnan(v)) continue;
      (j < 4 ? south : north) += v;
    }
  ASSERT_GT(south + north, 10) << "hardly any cell was oiled";
  EXPECT_LT(std::abs(south - north) / (south + north), 0.1) << south << " south, " << north;
  double left = 0, right = 0;
  for (const auto& b : summary["ensemble"]["bank_oiling_probability"])
    (b["bank"] == "left" ? left : right) += b["probability"].get<double>();
  ASSERT_GT(left + right, 1) << "the wind stranded almost nothing";
  EXPECT_LT(std::abs(left - right) / (left + right), 0.15)
      << left << " left, " << right << " right";
}

namespace {
// A log that raises the stop flag when the forecast says its steps are done: a Ctrl-C arriving
// while the outputs are written.
class StopWhenDone : public std::stringbuf {
 public:
  explicit StopWhenDone(std::atomic<bool>& stop) : stop_(stop) {}
  int sync() override {
    if (str().find("done in") != std::string::npos) stop_ = true;
    return 0;
  }

 private:
  std::atomic<bool>& stop_;
};
}  // namespace

// A Ctrl-C while the outputs are written ends the run with Interrupted (exit 130) and nothing
// written; it was swallowed, the run finishing and exiting 0 seconds later.
TEST_F(Forecast, AnInterruptionWhileWritingLeavesNothing) {
  std::ofstream(dir_ / "forecast.json") << config().dump(2);
  std::atomic<bool> stop{false};
  StopWhenDone buffer(stop);
  std::ostream log(&buffer);
  farfield::ForecastRunOptions o;
  o.config_file = (dir_ / "forecast.json").string();
  o.out_dir = (dir_ / "interrupted").string();
  o.stop = &stop;
  o.log = &log;
  EXPECT_THROW(farfield::run_forecast(o), common::Interrupted);
  EXPECT_TRUE(stop.load()) << "the steps never finished";
  EXPECT_FALSE(fs::exists(dir_ / "interrupted"));
}

// The flow of a reach that starts dry: its first output's velocity rasters are nodata everywhere,
// which a forecast starting there reads as still water (it failed with "every cell is nodata").
TEST_F(Forecast, AReachOutputWithNoWaterReadsAsDry) {
  farfield::ReachFlowRequest q;
  q.run_dir = (dir_ / "reach_run").string();
  q.start_time = 0;
  q.config_file = "forecast.json";
  q.pointer = "/flow";
  const farfield::ReachFlow flow(q);
  const farfield::FlowSample s = flow.sample(1771500, 5472040, 0);
  EXPECT_NE(s.where, farfield::FlowWhere::water);
  EXPECT_EQ(s.u, 0);
}
