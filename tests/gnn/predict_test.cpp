// spill-infer predict: a learned forecast from a scene alone, with the scene's own sources and
// sinks, written as spill-sim run's folder (infer/predict_command.cpp, gnn/eval/scene_rollout.h).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>

#include "common/config_error.h"
#include "gnn/data/dataset.h"
#include "gnn/training/checkpoint.h"
#include "infer/commands.h"
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
