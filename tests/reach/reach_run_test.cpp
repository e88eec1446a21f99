// A reach run from its config (reach/reach_run.h): a tilted channel written here as a GeoTIFF
// runs to its steady state and writes its folder; bad input is refused naming the key and
// leaves nothing behind.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <set>
#include <sstream>

#include "common/config_error.h"
#include "reach/raster.h"
#include "reach/reach_checks.h"
#include "reach/reach_run.h"

namespace fs = std::filesystem;

namespace {

class ReachRun : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("spill_reach_run_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    // A channel 400 m long with a flat bed 60 m wide falling 1 in 1000 to the west, between
    // banks 2 m high, on 10 m cells, in NZTM2000 coordinates.
    reach::Raster r;
    r.grid.nx = 40, r.grid.ny = 8, r.grid.dx = r.grid.dy = 10;
    r.grid.x0 = 1771000, r.grid.y0 = 5472000;
    for (int j = 0; j < r.grid.ny; ++j)
      for (int i = 0; i < r.grid.nx; ++i)
        r.values.push_back(0.001 * r.grid.x(i) - 1771.0 + ((j == 0 || j == 7) ? 2.0 : 0.0));
    r.crs_wkt = reach::crs_wkt_of("EPSG:2193");
    reach::write_geotiff((dir_ / "channel.tif").string(), r);
    config_ = {{"name", "channel"},
               {"terrain", {{"file", "channel.tif"}, {"manning", 0.03}}},
               {"inflows",
                {{{"section",
                   {{"name", "upstream"}, {"side", "east"}, {"from", 5472010}, {"to", 5472070}}},
                  {"discharge", {{"value", 6.0}}}}}},
               {"outflows",
                {{{"section",
                   {{"name", "downstream"}, {"side", "west"}, {"from", 5472010}, {"to", 5472070}}},
                  {"kind", "normal_depth"},
                  {"slope", 0.001}}}},
               {"end_time", 7200},
               {"output_every", 1000},
               {"steady_tolerance", 1e-6}};
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Writes the config and runs it into `out`.
  nlohmann::json run(const nlohmann::json& config, const std::string& out,
                     const std::vector<std::string>& overrides = {}) {
    std::ofstream(dir_ / "reach.json") << config.dump(2);
    reach::ReachRunOptions o;
    o.config_file = (dir_ / "reach.json").string();
    o.overrides = overrides;
    o.out_dir = (dir_ / out).string();
    o.log = &log_;
    return reach::run_reach(o);
  }
  // The message of the ConfigError a run throws ("" when it throws none).
  std::string refusal(const std::vector<std::string>& overrides) {
    try {
      run(config_, "refused", overrides);
    } catch (const common::InputError& e) {
      EXPECT_FALSE(fs::exists(dir_ / "refused")) << "a refused run wrote its folder";
      return e.what();
    }
    fs::remove_all(dir_ / "refused");  // accepted: the next case starts without it
    return "";
  }

  fs::path dir_;
  nlohmann::json config_;
  std::ostringstream log_;
};

}  // namespace

// The channel settles at the normal depth of its 6 m^3/s over its 60 m bed (q = 0.1 m^2/s,
// h_n = (n q / sqrt(S))^(3/5) = 0.243 m) and writes every file reach.json promises.
TEST_F(ReachRun, ATiltedChannelSettlesAndWritesItsFolder) {
  const nlohmann::json summary = run(config_, "out");
  const fs::path out = dir_ / "out";
  for (const char* f : {"reach.json", "map.png", "max_depth.tif", "max_level.tif", "bed.tif"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  EXPECT_TRUE(summary["steady"]["reached"].get<bool>());
  const auto& last = summary["frames"].back();
  EXPECT_NEAR(last["section_discharge_m3_s"]["upstream"].get<double>(), 6.0, 1e-9);
  EXPECT_NEAR(-last["section_discharge_m3_s"]["downstream"].get<double>(), 6.0, 0.03);
  EXPECT_LT(std::abs(summary["volume_balance"]["error_m3"].get<double>()), 1e-9);
  const reach::Raster depth =
      reach::read_raster((out / last["files"]["depth"].get<std::string>()).string());
  EXPECT_TRUE(fs::exists(out / last["files"]["map"].get<std::string>()));
  EXPECT_NE(depth.crs_wkt.find("NZGD2000"), std::string::npos);
  const double normal = std::pow(0.03 * 6.0 / 60.0 / std::sqrt(0.001), 0.6);
  EXPECT_NEAR(depth.values[depth.grid.at(20, 4)], normal, 0.01 * normal);
  EXPECT_NEAR(depth.values[depth.grid.at(20, 4)], last["max_depth_m"].get<double>(), 0.1);
  // bed.tif is the terrain the flow ran on (here the raster itself).
  const reach::Raster bed = reach::read_raster((out / "bed.tif").string());
  EXPECT_NEAR(bed.values[bed.grid.at(20, 4)], 0.001 * bed.grid.x(20) - 1771.0, 1e-4);
}

TEST_F(ReachRun, BadInputIsRefusedNamingTheKey) {
  EXPECT_NE(refusal({"/terrain/manning=-1"}).find("/terrain/manning"), std::string::npos);
  EXPECT_NE(refusal({"/terrain/windw=[0,0,1,1]"}).find("/terrain/windw: unknown key"),
            std::string::npos);
  EXPECT_NE(refusal({"/terrain/window=[0,0,10,10]"}).find("/terrain/window"), std::string::npos);
  EXPECT_NE(refusal({"/inflows/0/section/from=5471000", "/inflows/0/section/to=5471100"})
                .find("/inflows/0/section"),
            std::string::npos);
  const std::string missing = refusal({"/terrain/file=missing.tif"});
  EXPECT_NE(missing.find("reach.json:/terrain/file: "), std::string::npos) << missing;
  EXPECT_NE(missing.find("missing.tif"), std::string::npos) << missing;
  EXPECT_NE(refusal({"/terrain/crs=EPSG:4326"}).find("geographic"), std::string::npos);
  EXPECT_NE(refusal({"/terrain/crs=EPSG:999999"}).find("/terrain/crs"), std::string::npos);
  EXPECT_NE(refusal({"/inflows/0/discharge={\"value\": -1}"}).find("/inflows/0/discharge"),
            std::string::npos);
  // A raster without a CRS needs one named.
  reach::Raster plain = reach::read_raster((dir_ / "channel.tif").string());
  plain.crs_wkt.clear();
  reach::write_geotiff((dir_ / "plain.tif").string(), plain);
  EXPECT_NE(refusal({"/terrain/file=plain.tif"}).find("/terrain/crs"), std::string::npos);
  EXPECT_EQ(refusal({"/terrain/file=plain.tif", "/terrain/crs=EPSG:2193", "/end_time=10"}), "");
}

// A hydrograph from a CSV with dates, as the Waikanae record is written.
TEST_F(ReachRun, AHydrographReadsFromACsvWithDates) {
  std::ofstream(dir_ / "flow.csv") << "Date, Flow (m3/s), Code\n01/05/2005 00:00:00, 1.5, 0\n"
                                      "01/05/2005 00:05:00, 3.5, 0\n01/05/2005 00:10:00, 3.5, 0\n";
  nlohmann::json c = config_;
  c["inflows"][0]["discharge"] = {{"file", "flow.csv"}, {"time_format", "%m/%d/%Y %H:%M:%S"}};
  c["end_time"] = 600;
  c["steady_tolerance"] = 0;
  c["output_every"] = 150;
  const nlohmann::json summary = run(c, "csv");
  // At 150 s the discharge is halfway between 1.5 and 3.5 m^3/s; from 300 s on it is 3.5.
  EXPECT_NEAR(summary["frames"][1]["section_discharge_m3_s"]["upstream"].get<double>(), 2.5, 0.01);
  EXPECT_NEAR(summary["frames"][4]["section_discharge_m3_s"]["upstream"].get<double>(), 3.5, 1e-9);
  c["inflows"][0]["discharge"]["time_format"] = "seconds";
  try {
    run(c, "bad");
    ADD_FAILURE() << "a date read as seconds was accepted";
  } catch (const common::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("flow.csv:2"), std::string::npos) << e.what();
  }
}

// docs/reach_reference.md is `spill-sim reach-doc`'s output: regenerate it when a key changes
// (spill-sim reach-doc > docs/reach_reference.md).
TEST(ReachConfig, TheReferenceDocumentsEveryKey) {
  std::ifstream in(std::string(SPILL_SOURCE_DIR) + "/docs/reach_reference.md");
  const std::string doc((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(doc, reach::reach_reference_markdown());
}

// Every shipped reach config loads and places its sections on its raster.
TEST(ReachConfig, EveryShippedConfigBuilds) {
  int seen = 0;
  for (const auto& entry :
       fs::directory_iterator(std::string(SPILL_SOURCE_DIR) + "/configs/reach")) {
    if (entry.path().extension() != ".json") continue;
    const reach::ReachConfig c = reach::load_reach_config(entry.path().string(), {});
    const reach::ReachModel m = reach::build_reach(c, entry.path().string());
    EXPECT_GT(m.solver->grid().cells(), 1000u) << entry.path();
    // Within the step bound (the Waikanae flood took 218,653 steps for 137,128 estimated).
    EXPECT_LE(reach::check_run_length(c, m, entry.path().string()), c.max_steps) << entry.path();
    ++seen;
  }
  EXPECT_GE(seen, 1);
}

// An area inflow releases its discharge inside the grid: with no outflow, the reach holds
// exactly what came in, and the released water's level spreads over the bed.
TEST_F(ReachRun, AnAreaInflowReleasesItsDischargeInside) {
  nlohmann::json c = config_;
  c["inflows"] = {{{"name", "river"},
                   {"area", {1771150, 5472010, 1771250, 5472070}},
                   {"discharge", {{"value", 2.0}}}}};
  c["outflows"] = nlohmann::json::array();
  c["end_time"] = 300;
  c["output_every"] = 300;
  c["steady_tolerance"] = 0;
  const nlohmann::json summary = run(c, "area");
  const auto& last = summary["frames"].back();
  EXPECT_NEAR(last["volume_m3"].get<double>(), 2.0 * 300, 1e-9 * 600);
  EXPECT_DOUBLE_EQ(last["section_discharge_m3_s"]["river"].get<double>(), 2.0);
  c["inflows"][0]["area"] = {0, 0, 10, 10};
  std::ofstream(dir_ / "reach.json") << c.dump(2);
  EXPECT_THROW(run(c, "off"), common::ConfigError);
}

// Frames closer than a second apart each get their own files (they were named by whole seconds,
// so 3,001 frames shared 31 rasters), and a last frame just after an output does too.
TEST_F(ReachRun, FramesAHundredthOfASecondApartWriteTheirOwnFiles) {
  nlohmann::json c = config_;
  c["end_time"] = 0.05;
  c["output_every"] = 0.01;
  c["steady_tolerance"] = 0;
  const nlohmann::json summary = run(c, "fine");
  ASSERT_EQ(summary["frames"].size(), 6u);
  std::set<std::string> names;
  for (const auto& f : summary["frames"]) {
    const std::string depth = f["files"]["depth"].get<std::string>();
    EXPECT_TRUE(fs::exists(dir_ / "fine" / depth)) << depth;
    EXPECT_TRUE(fs::exists(dir_ / "fine" / f["files"]["map"].get<std::string>()));
    names.insert(depth);
  }
  EXPECT_EQ(names.size(), 6u);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_ / "fine" / "png"), fs::directory_iterator()),
            6);
  // Whole seconds stay as they were; a frame 0.2 s after the last output gets its decimals.
  EXPECT_EQ(reach::frame_stamp(600, 0, 600), "t0000600s");
  EXPECT_EQ(reach::frame_stamp(600.2, 600, 600), "t0000600.2s");
  EXPECT_NE(reach::frame_stamp(600.0004, 600, 600), reach::frame_stamp(600, 0, 600));
}

// Input that is wrong but looks fine is refused before any work, naming the key.
TEST_F(ReachRun, PlausibleButWrongInputIsRefusedNamingTheKey) {
  // An outflow on the inflow's cells: the balance would not close.
  const std::string overlap = refusal({"/outflows/0/section/side=\"east\""});
  EXPECT_NE(overlap.find("/outflows/0/section"), std::string::npos) << overlap;
  EXPECT_NE(overlap.find("/inflows/0/section"), std::string::npos) << overlap;
  // A CRS in US survey feet: 10 ft cells would run as 10 m cells.
  const std::string feet = refusal({"/terrain/crs=\"EPSG:2236\""});
  EXPECT_NE(feet.find("/terrain/crs"), std::string::npos) << feet;
  EXPECT_NE(feet.find("foot"), std::string::npos) << feet;
  // A hydrograph ending before the run, or starting late.
  EXPECT_NE(refusal({"/inflows/0/discharge={\"points\": [[0, 6], [100, 6]]}"})
                .find("/inflows/0/discharge: the series covers 0 to 100 s"),
            std::string::npos);
  EXPECT_NE(refusal({"/inflows/0/discharge={\"points\": [[10, 6], [8000, 6]]}"})
                .find("/inflows/0/discharge"),
            std::string::npos);
  EXPECT_EQ(refusal({"/inflows/0/discharge={\"points\": [[0, 6], [7200, 6]]}", "/end_time=10"}),
            "");
  // Roughness beyond any bed.
  EXPECT_NE(refusal({"/terrain/manning=1e30"}).find("/terrain/manning"), std::string::npos);
  // Elevations that are no ground: nodata values GDAL was not told of (infinities read as
  // nodata, as NaN does).
  for (const double z : {1e30, -3.4028235e38}) {
    reach::Raster r = reach::read_raster((dir_ / "channel.tif").string());
    r.values[r.grid.at(3, 3)] = z;
    reach::write_geotiff((dir_ / "odd.tif").string(), r);
    const std::string odd = refusal({"/terrain/file=\"odd.tif\""});
    EXPECT_NE(odd.find("/terrain/file"), std::string::npos) << odd;
    EXPECT_NE(odd.find("odd.tif has an elevation of"), std::string::npos) << odd;
  }
}

// A run that cannot end in a sensible number of steps is refused up front, naming what makes
// the steps short; one whose steps fall below the estimate stops at max_steps, writing nothing.
TEST_F(ReachRun, ARunTooLongToEndIsRefusedNamingWhatShortensItsSteps) {
  EXPECT_NE(refusal({"/inflows/0/discharge={\"value\": 1e30}"}).find("/inflows/0/discharge"),
            std::string::npos);
  // 4e9 m^3/s at the start of a hydrograph (the fuzzer's case ran for minutes at 0.2 ms steps)
  // would run 77 km deep; 6,000 m^3/s over the 60 m section (7.7 m) is a flood it can carry.
  const std::string deep = refusal({"/inflows/0/discharge={\"points\": [[0, 4e9], [7200, 6]]}"});
  EXPECT_NE(deep.find("/inflows/0/discharge: a peak of 4e+09"), std::string::npos) << deep;
  EXPECT_EQ(refusal({"/inflows/0/discharge={\"value\": 6000}", "/end_time=10"}), "");
  EXPECT_NE(refusal({"/cfl=1e-9"}).find("/cfl"), std::string::npos);
  EXPECT_NE(refusal({"/max_dt=1e-9"}).find("/max_dt"), std::string::npos);
  EXPECT_NE(refusal({"/output_every=1e-12"}).find("/output_every"), std::string::npos);
  EXPECT_NE(refusal({"/end_time=1e12", "/output_every=1e8"}).find("/end_time = 1e+12"),
            std::string::npos);
  // The estimate is a floor: this channel's 6 m^3/s over 60 m give waves of 2 m/s, steps of
  // 2.25 s, while the flow filling the dry channel runs faster.
  std::ofstream(dir_ / "reach.json") << config_.dump(2);
  const std::string file = (dir_ / "reach.json").string();
  const reach::ReachConfig c = reach::load_reach_config(file, {"/end_time=600"});
  const reach::ReachModel m = reach::build_reach(c, file);
  const double least = reach::check_run_length(c, m, file);
  EXPECT_NEAR(least, std::ceil(600 / (0.45 * 10 / (2 * std::sqrt(9.81 * std::cbrt(0.01 / 9.81))))),
              1);
  const std::string stopped =
      refusal({"/end_time=600", "/max_steps=" + std::to_string(long(least))});
  EXPECT_NE(stopped.find("/max_steps: the run passed"), std::string::npos) << stopped;
}

// A terrain too large to read or run within the memory this process may use is refused before
// reading it, naming the window (read) or the coarsening (run).
TEST_F(ReachRun, ATerrainBeyondTheMemoryIsRefusedBeforeItIsRead) {
  const reach::Raster header = reach::raster_header((dir_ / "channel.tif").string());
  EXPECT_EQ(header.grid.nx, 40);
  EXPECT_TRUE(header.values.empty());
  reach::TerrainConfig t;
  t.file = "channel.tif";
  const double cells = 40 * 8;
  // A strip of one row and the grid read, the grid run.
  const double need = (40 + cells) * reach::kBytesPerCellRead + cells * reach::kBytesPerReachCell;
  EXPECT_NO_THROW(reach::check_terrain_size(header, t, need, "reach.json"));
  try {
    reach::check_terrain_size(header, t, need - 1, "reach.json");
    ADD_FAILURE() << "a terrain over the memory was accepted";
  } catch (const common::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("reach.json:/terrain/window: 320 cells"),
              std::string::npos)
        << e.what();
  }
  // Read it fits, run it does not: coarsen it.
  t.window = {1771000, 5472000, 1771400, 5472080};
  try {
    reach::check_terrain_size(header, t, (40 + cells) * reach::kBytesPerCellRead * 2, "reach.json");
    ADD_FAILURE() << "a grid over the memory was accepted";
  } catch (const common::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("/terrain/coarsen"), std::string::npos) << e.what();
  }
  t.coarsen = 4;  // 10 x 2 cells, read in strips of 4 rows of 40
  EXPECT_NO_THROW(reach::check_terrain_size(
      header, t, (160 + 20) * reach::kBytesPerCellRead + 20 * reach::kBytesPerReachCell,
      "reach.json"));
}
