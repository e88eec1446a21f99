// spill-infer predict: a learned forecast from a scene alone, with the scene's own sources and
// sinks, written as spill-sim run's folder (infer/predict_command.cpp, gnn/eval/scene_rollout.h);
// with --members K, K forecasts in one process, the first the unperturbed forecast of the folder,
// the others from jittered starts, summarised per frame by quantiles over the members and by a
// probability-of-oiling picture (infer/forecast_ensemble.h).
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <set>

#include "common/config_error.h"
#include "gnn/data/dataset.h"
#include "gnn/training/checkpoint.h"
#include "infer/commands.h"
#include "infer/forecast_ensemble.h"
#include "sph/app/scene_runner.h"
#include "sph/scene/scene_loader.h"
#include "tests/gnn/run_folder.h"

namespace fs = std::filesystem;

namespace {

const std::string kSource = SPILL_SOURCE_DIR;
// Models of the committed results: DPI-Nets is the fastest learned model (a frame of river_small
// in about 10 ms). dpi.pt was trained at 0.05 s per frame, dpi_f20.pt at 0.1 s.
const std::string kDpi = kSource + "/docs/results/baselines/dpi.pt";
const std::string kDpiTenthSecond = kSource + "/docs/results/crossover_runs/dpi_f20.pt";
const std::string kRiverSmall = kSource + "/configs/scenes/river_small.json";
const std::string kRiverCase1 = kSource + "/configs/scenes/river_case1.json";

fs::path temp_dir(const std::string& name) {
  fs::path p =
      fs::temp_directory_path() / ("spill_predict_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

nlohmann::json read_json(const fs::path& file) {
  std::ifstream in(file);
  return nlohmann::json::parse(in);
}

infer::PredictOptions options(const std::string& checkpoint, const std::string& scene,
                              const fs::path& out, std::vector<std::string> overrides) {
  infer::PredictOptions o;
  o.checkpoint = checkpoint;
  o.scene_file = scene;
  o.out_dir = out.string();
  o.overrides = std::move(overrides);
  o.threads = 1;
  return o;
}

// Oil volume (m^3) on the water at the last frame, and retired before it (each retired particle
// with the oil fraction of its last active frame); every particle has the rest volume `volume`.
std::pair<double, double> oil_accounts(const gnn::Trajectory& t, double volume) {
  const int64_t last = t.frames() - 1;
  const auto on_water = (t.oil_fraction[last] * t.active[last]).sum().item<double>() * volume;
  double retired = 0;
  const auto ever = t.active.any(0);
  for (int64_t p = 0; p < t.particles(); ++p) {
    if (!ever[p].item<bool>() || t.active[last][p].item<bool>()) continue;
    int64_t k = last;
    while (!t.active[k][p].item<bool>()) --k;
    retired += t.oil_fraction[k][p].item<double>() * volume;
  }
  return {on_water, retired};
}

std::set<std::string> keys(const nlohmann::json& j) {
  std::set<std::string> out;
  for (auto it = j.begin(); it != j.end(); ++it) out.insert(it.key());
  return out;
}

// river_small with a short leak passing an intake 0.6 m downstream, and a watch point the oil
// cannot reach in the forecast, as `members` forecasts (--members).
infer::PredictOptions short_leak(const fs::path& out, int members) {
  infer::PredictOptions o =
      options(kDpi, kRiverSmall, out,
              {"/leaks/0/start=0.3", "/leaks/0/duration=0.7", "/end_time=1.4",
               R"(/watch_points=[{"name":"intake","x":1.6,"y":0.0,"radius":0.2},)"
               R"({"name":"far","x":3.5,"y":0.0}])"});
  o.members = members;
  return o;
}

const double kInf = std::numeric_limits<double>::infinity();
const double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

// river_small from the scene file alone, its whole leak (1 s of 4 l/s from t = 0.3 s) inside the
// forecast: the folder reads as spill-sim run's, and the oil released is the leak's to within a
// particle's volume, all of it either on the water or retired at the outflow at the end.
TEST(Predict, RiverSmallFromTheSceneAloneReleasesTheWholeLeak) {
  const fs::path dir = temp_dir("river_small");
  const std::vector<std::string> set = {"/leaks/0/start=0.3", "/leaks/0/duration=1.0",
                                        "/end_time=1.6"};
  const nlohmann::json summary =
      infer::run_predict(options(kDpi, kRiverSmall, dir / "predicted", set));
  EXPECT_EQ(summary["frames"], 32);
  const fs::path run = dir / "predicted";
  for (const char* file :
       {"metadata.json", "trajectory.h5", "stats.json", "spill.json", "spill.svg", "report.html"})
    EXPECT_TRUE(fs::exists(run / file)) << file;
  const nlohmann::json metadata = read_json(run / "metadata.json");
  EXPECT_EQ(metadata["predicted_by"]["checkpoint"], kDpi);
  EXPECT_EQ(metadata["predicted_by"]["model"], "dpi");
  {
    // The report says which model predicted it.
    std::ifstream in(run / "report.html");
    const std::string page((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_NE(page.find("<td>predicted by</td><td>dpi ("), std::string::npos);
  }

  // spill-sim run's folder for the same scene has the same files and spill.json keys.
  sph::RunOptions sph_run;
  sph_run.out_dir = dir / "simulated";
  sph::run_scene(sph::load_scene(kRiverSmall, set), sph_run);
  const nlohmann::json predicted_spill = read_json(run / "spill.json");
  const nlohmann::json simulated_spill = read_json(dir / "simulated" / "spill.json");
  EXPECT_EQ(keys(predicted_spill), keys(simulated_spill));
  EXPECT_EQ(keys(predicted_spill["frames"].back()), keys(simulated_spill["frames"].back()));
  ASSERT_EQ(predicted_spill["frames"].size(), simulated_spill["frames"].size());

  const gnn::Trajectory t = run_folder::read(run, dir / "view").trajectory;
  EXPECT_EQ(t.frames(), 33);
  EXPECT_NEAR(t.time[32].item<double>(), 1.6, 1e-9);
  const double volume = 0.05 * 0.05 * 0.05;  // a particle of radius 0.025 m
  const double leak = 0.004 * 1.0;
  const double released = predicted_spill["frames"].back()["oil_released_m3"];
  EXPECT_NEAR(released, leak, volume);
  // The same emitter code releases the same oil in the solver's run.
  EXPECT_DOUBLE_EQ(released, simulated_spill["frames"].back()["oil_released_m3"].get<double>());
  const auto [on_water, retired] = oil_accounts(t, volume);
  EXPECT_NEAR(on_water + retired, released, volume) << on_water << " + " << retired;
  EXPECT_GT(on_water, 0.5 * released);  // 0.3 s after the leak, most oil is still in the reach
  fs::remove_all(dir);
}

// river_case1 (20,000 particles, its leak from the left bank) with a model of its frame interval.
TEST(Predict, RiverCase1RunsFromTheSceneAlone) {
  const fs::path dir = temp_dir("river_case1");
  const std::vector<std::string> set = {"/leaks/0/start=0.1", "/leaks/0/duration=0.4",
                                        "/end_time=0.6"};
  infer::run_predict(options(kDpiTenthSecond, kRiverCase1, dir / "predicted", set));
  const gnn::Trajectory t = run_folder::read(dir / "predicted", dir / "view").trajectory;
  EXPECT_EQ(t.frames(), 7);
  const nlohmann::json spill = read_json(dir / "predicted" / "spill.json");
  const double volume = 0.05 * 0.05 * 0.05;
  const double released = spill["frames"].back()["oil_released_m3"];
  EXPECT_NEAR(released, 0.02 * 0.4, volume);
  const auto [on_water, retired] = oil_accounts(t, volume);
  EXPECT_NEAR(on_water + retired, released, volume);
  fs::remove_all(dir);
}

// A checkpoint refuses a scene unlike its data, naming the key and both values, and writes
// nothing.
TEST(Predict, RefusesASceneUnlikeTheModelsData) {
  const fs::path dir = temp_dir("refusals");
  const auto refused = [&](const std::string& checkpoint, const std::string& scene,
                           const std::vector<std::string>& set) -> std::string {
    try {
      infer::run_predict(options(checkpoint, scene, dir / "out", set));
    } catch (const common::ConfigError& e) {
      EXPECT_FALSE(fs::exists(dir / "out"));
      return e.what();
    }
    ADD_FAILURE() << "accepted";
    return "";
  };
  const std::string frame = refused(kDpi, kRiverCase1, {});
  EXPECT_NE(frame.find("river_case1.json:/output/frame_dt"), std::string::npos) << frame;
  EXPECT_NE(frame.find("0.1"), std::string::npos) << frame;
  EXPECT_NE(frame.find("0.05"), std::string::npos) << frame;
  const std::string radius = refused(kDpi, kRiverSmall, {"/particle_radius=0.02"});
  EXPECT_NE(radius.find(":/particle_radius"), std::string::npos) << radius;
  EXPECT_NE(radius.find("0.02"), std::string::npos) << radius;
  EXPECT_NE(radius.find("0.025"), std::string::npos) << radius;

  // A model whose data held no oil, asked about a leak.
  auto loaded = gnn::load_checkpoint(kDpi);
  nlohmann::json water_only = loaded.data;
  water_only["particle_types"] = {{"water", 0}, {"boundary", 2}};
  const std::string water_model = (dir / "water_only.pt").string();
  gnn::save_checkpoint(water_model, *loaded.simulator, water_only, loaded.state, nullptr);
  const std::string kind = refused(water_model, kRiverSmall, {});
  EXPECT_NE(kind.find(":/leaks"), std::string::npos) << kind;
  EXPECT_NE(kind.find("oil"), std::string::npos) << kind;
  fs::remove_all(dir);
}

// Hyndman & Fan's type 7 (numpy's default): q (n - 1) between order statistics.
TEST(ForecastEnsemble, QuantilesInterpolateBetweenOrderStatistics) {
  const std::vector<double> v = {1, 2, 3, 4};
  EXPECT_NEAR(infer::quantile_of_sorted(v, 0.1), 1.3, 1e-12);
  EXPECT_NEAR(infer::quantile_of_sorted(v, 0.5), 2.5, 1e-12);
  EXPECT_NEAR(infer::quantile_of_sorted(v, 0.9), 3.7, 1e-12);
  EXPECT_EQ(infer::quantile_of_sorted(v, 0), 1);
  EXPECT_EQ(infer::quantile_of_sorted(v, 1), 4);
  // A member that never arrived sorts last: quantiles below it stay finite.
  const std::vector<double> late = {1, 2, kInf};
  EXPECT_NEAR(infer::quantile_of_sorted(late, 0.25), 1.5, 1e-12);
  EXPECT_EQ(infer::quantile_of_sorted(late, 0.5), 2);
  EXPECT_EQ(infer::quantile_of_sorted(late, 0.9), kInf);
  EXPECT_THROW(infer::quantile_of_sorted({}, 0.5), std::invalid_argument);
  EXPECT_THROW(infer::quantile_of_sorted(v, 1.5), std::invalid_argument);

  // Members that do not define a figure (NaN) are left out and counted.
  const infer::Spread s = infer::spread_of({3, kNaN, 1, 2});
  EXPECT_EQ(s.members, 3);
  EXPECT_NEAR(s.mean, 2, 1e-12);
  EXPECT_NEAR(s.q10, 1.2, 1e-12);
  EXPECT_NEAR(s.q50, 2, 1e-12);
  EXPECT_NEAR(s.q90, 2.8, 1e-12);
  const infer::Spread none = infer::spread_of({kNaN, kNaN});
  EXPECT_EQ(none.members, 0);
  EXPECT_TRUE(std::isnan(none.mean));
}

// Three members reach a watch point at 1 s, at 2 s and never: by each frame the share that has
// arrived, and the arrival quantiles with "never" as after the end.
TEST(ForecastEnsemble, ArrivalCountsAMemberThatNeverArrivedAsAfterTheEnd) {
  const std::vector<double> times = {0, 1, 2, 3};
  std::vector<infer::MemberTrack> members(3);
  for (size_t k = 0; k < 3; ++k) {
    members[k].front = {0, 1, 2, 3 + double(k)};
    members[k].slick_area = {0, 0.1, 0.2, 0.3};
    members[k].centroid_x = {kNaN, 1, 2, 3};
    members[k].centroid_y = {kNaN, 0, 0, 0};
  }
  members[0].arrival["intake"] = 1.0;
  members[1].arrival["intake"] = 2.0;
  members[2].arrival["intake"] = std::nullopt;
  const nlohmann::json j = infer::ensemble_summary(members, times);
  const nlohmann::json& intake = j["watch_point_arrival_s"]["intake"];
  EXPECT_NEAR(intake["share_reached"].get<double>(), 2.0 / 3, 1e-12);
  const std::vector<double> by_frame = intake["share_reached_by_frame"];
  ASSERT_EQ(by_frame.size(), 4u);
  EXPECT_NEAR(by_frame[0], 0, 1e-12);
  EXPECT_NEAR(by_frame[1], 1.0 / 3, 1e-12);
  EXPECT_NEAR(by_frame[2], 2.0 / 3, 1e-12);
  EXPECT_NEAR(by_frame[3], 2.0 / 3, 1e-12);
  EXPECT_NEAR(intake["q10"].get<double>(), 1.2, 1e-12);
  EXPECT_NEAR(intake["q50"].get<double>(), 2.0, 1e-12);
  EXPECT_TRUE(intake["q90"].is_null());
  // The last frame's fronts are 3, 4 and 5 m; no member has a centroid at the first frame.
  EXPECT_NEAR(j["front_m"][3]["mean"].get<double>(), 4, 1e-12);
  EXPECT_NEAR(j["front_m"][3]["q90"].get<double>(), 4.8, 1e-12);
  EXPECT_EQ(j["centroid_x_m"][0]["members"], 0);
  EXPECT_TRUE(j["centroid_x_m"][0]["mean"].is_null());
  members[2].front.pop_back();
  EXPECT_THROW(infer::ensemble_summary(members, times), std::invalid_argument);
}

// The first member is the forecast predict writes without --members; the others start jittered
// and differ; ensemble.json's figures are those of the members' own spill.json.
TEST(PredictMembers, FirstMemberIsTheForecastAndTheSummaryIsTheMembers) {
  const fs::path dir = temp_dir("three");
  infer::run_predict(short_leak(dir / "one", 1));
  const nlohmann::json summary = infer::run_predict(short_leak(dir / "three", 3));
  const fs::path run = dir / "three";
  for (const char* file : {"trajectory.h5", "spill.json", "ensemble.json", "oiling.png",
                           "members/01/spill.json", "members/03/spill.json", "report.html"})
    EXPECT_TRUE(fs::exists(run / file)) << file;
  EXPECT_FALSE(fs::exists(dir / "one" / "ensemble.json"));
  EXPECT_EQ(read_json(run / "spill.json"), read_json(dir / "one" / "spill.json"));
  EXPECT_EQ(summary["members"]["count"], 3);
  EXPECT_EQ(summary["members"]["wall_s"].size(), 3u);
  EXPECT_GT(summary["start_up_s"].get<double>(), 0);
  EXPECT_EQ(read_json(run / "metadata.json")["predicted_by"]["members"], 3);

  std::vector<nlohmann::json> spill;
  for (const char* m : {"01", "02", "03"})
    spill.push_back(read_json(run / "members" / m / "spill.json"));
  EXPECT_EQ(spill[0], read_json(run / "spill.json"));
  const size_t frames = spill[0]["frames"].size();
  bool differ = false;
  for (size_t k = 1; k < 3; ++k) {
    ASSERT_EQ(spill[k]["frames"].size(), frames);
    for (size_t f = 0; f < frames; ++f) {
      // The same leak releases the same oil in every member.
      EXPECT_EQ(spill[k]["frames"][f]["oil_released_m3"], spill[0]["frames"][f]["oil_released_m3"]);
      differ = differ || spill[k]["frames"][f]["front_distance_m"] !=
                             spill[0]["frames"][f]["front_distance_m"];
    }
  }
  EXPECT_TRUE(differ) << "the jittered members forecast exactly the unperturbed front";

  const nlohmann::json ensemble = read_json(run / "ensemble.json");
  ASSERT_EQ(ensemble["front_m"].size(), frames);
  for (size_t f = 0; f < frames; ++f) {
    std::vector<double> fronts;
    for (const auto& s : spill) fronts.push_back(s["frames"][f]["front_distance_m"]);
    const nlohmann::json& front = ensemble["front_m"][f];
    EXPECT_NEAR(front["mean"].get<double>(), (fronts[0] + fronts[1] + fronts[2]) / 3, 1e-9) << f;
    const auto [low, high] = std::minmax_element(fronts.begin(), fronts.end());
    EXPECT_GE(front["q10"].get<double>(), *low - 1e-12);
    EXPECT_LE(front["q10"].get<double>(), front["q50"].get<double>());
    EXPECT_LE(front["q50"].get<double>(), front["q90"].get<double>());
    EXPECT_LE(front["q90"].get<double>(), *high + 1e-12);
  }
  for (const char* name : {"intake", "far"}) {
    int reached = 0;
    for (const auto& s : spill) reached += s["arrival_s"][name].is_null() ? 0 : 1;
    EXPECT_NEAR(ensemble["watch_point_arrival_s"][name]["share_reached"].get<double>(),
                reached / 3.0, 1e-12)
        << name;
  }
  // The oil reaches the intake 0.6 m downstream within the forecast, never the far one at 2.5 m.
  EXPECT_GT(ensemble["watch_point_arrival_s"]["intake"]["share_reached"].get<double>(), 0);
  EXPECT_EQ(ensemble["watch_point_arrival_s"]["far"]["share_reached"].get<double>(), 0);
  // The oiling picture's moments lie after the leak's start (0.3 s), the last at the end.
  const std::vector<double> moments = ensemble["oiling_png"]["t"];
  ASSERT_FALSE(moments.empty());
  EXPECT_GT(moments.front(), 0.3);
  EXPECT_NEAR(moments.back(), 1.4, 1e-9);
  fs::remove_all(dir);
}

// A forecast that ends before its leak starts still has an ensemble: no oil anywhere, and the
// oiling picture at its last frame.
TEST(PredictMembers, AForecastEndingBeforeTheLeakHasAnEnsembleWithoutOil) {
  const fs::path dir = temp_dir("before_leak");
  infer::PredictOptions o = short_leak(dir / "out", 2);
  o.overrides = {"/leaks/0/start=1.0", "/end_time=0.5"};
  infer::run_predict(o);
  const nlohmann::json ensemble = read_json(dir / "out" / "ensemble.json");
  const std::vector<double> moments = ensemble["oiling_png"]["t"];
  ASSERT_EQ(moments.size(), 1u);
  EXPECT_NEAR(moments.front(), 0.5, 1e-9);
  EXPECT_EQ(ensemble["front_m"].back()["q90"].get<double>(), 0);  // no oil, no front
  EXPECT_TRUE(fs::exists(dir / "out" / "oiling.png"));
  fs::remove_all(dir);
}

// An ensemble summarises a river leak's metrics: a scene without one is refused before anything
// is written.
TEST(PredictMembers, RefusesASceneWithoutARiverLeak) {
  const fs::path dir = temp_dir("still");
  infer::PredictOptions o = short_leak(dir / "out", 2);
  o.scene_file = kSource + "/configs/scenes/slick_still_water.json";
  o.overrides.clear();
  try {
    infer::run_predict(o);
    ADD_FAILURE() << "accepted";
  } catch (const common::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("slick_still_water.json:/leaks"), std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(fs::exists(dir / "out"));
  fs::remove_all(dir);
}
