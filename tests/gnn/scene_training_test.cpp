// Training straight from the simulator (`spill-train --scene`): the in-process trajectories are
// the ones `spill-sim generate` writes for the same options and the ones --save-data writes, a
// run from a scene trains exactly as one on its saved dataset, a resumed run re-simulates the
// same data, and bad input is a clear error that leaves no run folder.
#include <gtest/gtest.h>
#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "gnn/data/dataset.h"
#include "gnn/data/simulated_dataset.h"
#include "gnn/eval/standalone_skill.h"
#include "gnn/training/checkpoint.h"
#include "sph/generation/dataset_folder.h"
#include "sph/generation/generation.h"
#include "tests/gnn/training_log.h"

namespace fs = std::filesystem;

namespace {

// A dam break of 125 particles in a 0.4 m box, 10 frames of 0.02 s: a trajectory simulates in a
// fraction of a second.
fs::path tiny_scene(const fs::path& dir) {
  fs::create_directories(dir);
  const fs::path file = dir / "tiny_scene.json";
  std::ofstream(file) << R"({
    "name": "tiny", "particle_radius": 0.02, "end_time": 0.2, "output": {"frame_dt": 0.02},
    "boxes": [{"min": [0, 0, 0], "max": [0.4, 0.4, 0.4]}],
    "fluid_blocks": [{"min": [0, 0, 0], "max": [0.2, 0.2, 0.2], "velocity": [0, 0, 0]}]})";
  return file;
}

struct Ran {
  int code = -1;
  std::string err;  // stderr
};

Ran run(const std::string& command, const fs::path& dir) {
  const fs::path err = dir / "stderr.txt";
  const int status = std::system((command + " > /dev/null 2> " + err.string()).c_str());
  Ran r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream in(err);
  std::stringstream s;
  s << in.rdbuf();
  r.err = s.str();
  return r;
}

nlohmann::json read_json(const fs::path& file) {
  std::ifstream in(file);
  return nlohmann::json::parse(in);
}

void expect_same_trajectories(const std::vector<gnn::Trajectory>& a,
                              const std::vector<gnn::Trajectory>& b, const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (size_t k = 0; k < a.size(); ++k) {
    SCOPED_TRACE(what + " trajectory " + std::to_string(k) + ": " + a[k].source + " vs " +
                 b[k].source);
    EXPECT_TRUE(torch::equal(a[k].position, b[k].position));  // bit for bit
    EXPECT_TRUE(torch::equal(a[k].velocity, b[k].velocity));
    EXPECT_TRUE(torch::equal(a[k].active, b[k].active));
    EXPECT_TRUE(torch::equal(a[k].particle_type, b[k].particle_type));
    EXPECT_TRUE(torch::equal(a[k].boundary, b[k].boundary));
    EXPECT_TRUE(torch::equal(a[k].time, b[k].time));
    EXPECT_TRUE(torch::equal(a[k].material, b[k].material));
    EXPECT_TRUE(torch::equal(a[k].oil_fraction, b[k].oil_fraction));
    EXPECT_EQ(a[k].scene, b[k].scene);
  }
}

// Both descriptions of one dataset without what depends on the wall clock.
nlohmann::json without_timing(nlohmann::json metadata) {
  for (auto& t : metadata["trajectories"])
    for (const char* key : {"sph_wall_s", "sph_seconds_per_frame"}) t.erase(key);
  return metadata;
}

class SceneTraining : public ::testing::Test {
 protected:
  void SetUp() override {
    threads_ = omp_get_max_threads();
    omp_set_num_threads(1);  // bit-reproducible simulations
    dir_ = fs::temp_directory_path() /
           ("scene_training_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
            std::to_string(getpid()));
    fs::remove_all(dir_);
    scene_ = tiny_scene(dir_);
  }
  void TearDown() override {
    omp_set_num_threads(threads_);
    fs::remove_all(dir_);
  }
  sph::GenerateOptions generate_options() const {
    sph::GenerateOptions o;
    o.scene_file = scene_.string();
    o.trajectories = 3;
    o.vary = {sph::parse_parameter_range("/fluid_blocks/0/velocity/0=0:1")};
    o.seed = 7;
    o.split = {0.34, 0.33, 0.33};
    o.frames = 9;
    return o;
  }
  // spill-train on the tiny scene with spill-sim generate's options as above.
  std::string train_from_scene(const std::string& seed = "7",
                               const std::string& split = "0.34/0.33/0.33") const {
    return std::string(SPILL_TRAIN_EXE) + " --config " + SPILL_SOURCE_DIR +
           "/configs/training/gns_smoke.json --scene " + scene_.string() +
           " --trajectories 3 --vary /fluid_blocks/0/velocity/0=0:1 --seed " + seed + " --split " +
           split +
           " --frames 9 --set /validate_every=10 --set /checkpoint_every=10 --set /log_every=5";
  }
  int threads_ = 1;
  fs::path dir_, scene_;
};

}  // namespace

// The trajectories handed to the trainer are those --save-data writes (read back by the --data
// reader: positions bit-identical, the same statistics) and those spill-sim generate writes for
// the same options: the same draws, splits, warm-up, frames and metadata.
TEST_F(SceneTraining, InProcessDataEqualTheSavedDatasetAndTheGenerators) {
  const sph::GenerateOptions o = generate_options();
  const gnn::SimulatedDataset simulated = gnn::simulate_dataset(o, (dir_ / "saved").string());
  ASSERT_EQ(simulated.train.size(), 1u);
  ASSERT_EQ(simulated.valid.size(), 1u);
  ASSERT_EQ(simulated.test.size(), 1u);
  EXPECT_EQ(simulated.train[0].frames(), 9);
  EXPECT_EQ(simulated.train[0].particles(), 125);

  const gnn::DatasetMetadata saved = gnn::read_metadata((dir_ / "saved/metadata.json").string());
  EXPECT_EQ(saved.raw, simulated.metadata.raw);
  for (const char* key : {"vel_mean", "vel_std", "acc_mean", "acc_std"})
    EXPECT_EQ(saved.raw.at(key), simulated.metadata.raw.at(key)) << key;
  EXPECT_TRUE(torch::equal(saved.vel_mean, simulated.metadata.vel_mean));
  EXPECT_TRUE(torch::equal(saved.vel_std, simulated.metadata.vel_std));
  EXPECT_TRUE(torch::equal(saved.acc_mean, simulated.metadata.acc_mean));
  EXPECT_TRUE(torch::equal(saved.acc_std, simulated.metadata.acc_std));
  EXPECT_GT(saved.vel_std[0].item<float>(), 0);
  for (const auto& t : saved.raw.at("trajectories")) EXPECT_EQ(t.at("simulation_threads"), 1);
  const std::string saved_dir = (dir_ / "saved").string();
  expect_same_trajectories(simulated.train, gnn::read_split(saved_dir, "train", saved), "train");
  expect_same_trajectories(simulated.valid, gnn::read_split(saved_dir, "valid", saved), "valid");
  expect_same_trajectories(simulated.test, gnn::read_split(saved_dir, "test", saved), "test");
  EXPECT_EQ(gnn::read_split(saved_dir, "train", saved)[0].sph_seconds_per_frame,
            simulated.train[0].sph_seconds_per_frame);
  // Nothing but the dataset's files (no parts, no staging folder beside it).
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(dir_ / "saved"))
    files.push_back(e.path().filename().string());
  std::sort(files.begin(), files.end());
  EXPECT_EQ(files, (std::vector<std::string>{"metadata.json", "test.h5", "train.h5", "valid.h5"}));
  for (const auto& e : fs::directory_iterator(dir_))
    EXPECT_NE(e.path().filename().string()[0], '.') << e.path();

  sph::GenerateOptions g = o;
  g.out_dir = dir_ / "generated";
  const nlohmann::json generated = sph::generate_dataset(g).metadata;
  EXPECT_EQ(without_timing(generated), without_timing(simulated.metadata.raw));
  const gnn::DatasetMetadata generated_meta =
      gnn::read_metadata((dir_ / "generated/metadata.json").string());
  for (const char* split : {"train", "valid", "test"})
    expect_same_trajectories(gnn::read_split(saved_dir, split, saved),
                             gnn::read_split(g.out_dir.string(), split, generated_meta), split);

  // Deterministic on one thread: the same fingerprint again; a saved dataset is never replaced.
  EXPECT_EQ(gnn::simulate_dataset(o).fingerprint, simulated.fingerprint);
  EXPECT_THROW(gnn::simulate_dataset(o, (dir_ / "saved").string()), common::InputError);
  EXPECT_TRUE(fs::exists(dir_ / "saved/metadata.json"));
}

// One command from a scene to a trained model; it trains exactly as --data on the saved dataset
// does, and --resume re-simulates the data from the seed (refusing other settings).
TEST_F(SceneTraining, TrainsFromASceneAsOnItsSavedDatasetAndResumes) {
  const std::string train = train_from_scene();
  const fs::path from_scene = dir_ / "from_scene", data = dir_ / "data";
  Ran r = run(train + " --threads 1 --set /steps=20 --save-data " + data.string() + " --out " +
                  from_scene.string(),
              dir_);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("trajectory 3/3 (test)"), std::string::npos) << r.err;  // progress
  ASSERT_TRUE(fs::exists(from_scene / "last.pt"));
  EXPECT_FALSE(fs::exists(from_scene / "best.pt"));  // best_checkpoint_trajectories is 0
  const auto rows = training_log::rows_without_timing(from_scene / "log.csv");
  ASSERT_EQ(rows.size(), 5u);  // header and steps 5, 10, 15, 20
  const gnn::LoadedCheckpoint checkpoint = gnn::load_checkpoint((from_scene / "last.pt").string());
  EXPECT_EQ(checkpoint.state.step, 20);
  EXPECT_EQ(checkpoint.simulator->model().name(), "gns");
  const nlohmann::json description = read_json(from_scene / "config.json").at("data");
  EXPECT_EQ(description.at("generation").at("seed"), 7);
  EXPECT_EQ(description.at("fingerprint").get<std::string>().size(), 16u);
  EXPECT_TRUE(fs::exists(data / "test.h5"));

  // The same training on the saved dataset: the same log, row for row.
  const fs::path from_data = dir_ / "from_data";
  r = run(std::string(SPILL_TRAIN_EXE) + " --config " + SPILL_SOURCE_DIR +
              "/configs/training/gns_smoke.json --data " + data.string() +
              " --threads 1 --set /steps=20 --set /validate_every=10 --set /checkpoint_every=10 "
              "--set /log_every=5 --out " +
              from_data.string(),
          dir_);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(training_log::rows_without_timing(from_data / "log.csv"), rows);

  // Interrupted at step 10 and resumed: the data simulated again are the same, and so is the log.
  const fs::path resumed = dir_ / "resumed";
  ASSERT_EQ(run(train + " --threads 1 --set /steps=10 --out " + resumed.string(), dir_).code, 0);
  r = run(train + " --threads 1 --set /steps=20 --resume --out " + resumed.string(), dir_);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(training_log::rows_without_timing(resumed / "log.csv"), rows);
  // Other draws are other data: refused before anything changes, naming the setting.
  r = run(train_from_scene("8") + " --threads 1 --set /steps=30 --resume --out " + resumed.string(),
          dir_);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("/data/generation/seed"), std::string::npos) << r.err;
  EXPECT_EQ(training_log::rows_without_timing(resumed / "log.csv"), rows);
  // A run trained on a folder is resumed with --data.
  r = run(train + " --threads 1 --set /steps=30 --resume --out " + from_data.string(), dir_);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--data instead of --scene"), std::string::npos) << r.err;

  // Data that come out otherwise (here: the scene file was edited) are refused by their
  // fingerprint.
  ASSERT_EQ(
      run(train + " --threads 1 --set /steps=10 --out " + (dir_ / "edited").string(), dir_).code,
      0);
  std::ofstream(scene_) << R"({"name": "tiny", "particle_radius": 0.02, "end_time": 0.2,
    "output": {"frame_dt": 0.02}, "boxes": [{"min": [0, 0, 0], "max": [0.4, 0.4, 0.4]}],
    "fluid_blocks": [{"min": [0, 0, 0], "max": [0.2, 0.2, 0.16], "velocity": [0, 0, 0]}]})";
  r = run(train + " --threads 1 --set /steps=20 --resume --out " + (dir_ / "edited").string(),
          dir_);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("/data/fingerprint"), std::string::npos) << r.err;
  EXPECT_EQ(training_log::rows_without_timing(dir_ / "edited/log.csv").size(),
            3u);  // header, steps 5 and 10

  // The simulation runs on every --threads thread, LibTorch's first operation notwithstanding.
  const fs::path two = dir_ / "two_threads";
  r = run(train + " --threads 2 --set /steps=1 --save-data " + (dir_ / "data2").string() +
              " --out " + two.string(),
          dir_);
  ASSERT_EQ(r.code, 0) << r.err;
  for (const auto& t : read_json(dir_ / "data2/metadata.json").at("trajectories"))
    EXPECT_EQ(t.at("simulation_threads"), 2) << t.dump();
}

// Bad input exits 2 naming what is wrong, before anything is simulated or written: no run
// folder, no saved dataset.
TEST_F(SceneTraining, BadInputExitsNamingItAndLeavesNoRunFolder) {
  const std::string train = train_from_scene() + " --threads 1 --set /steps=2";
  const fs::path out = dir_ / "run", data = dir_ / "data";
  const std::string out_and_data = " --out " + out.string() + " --save-data " + data.string();
  auto expect_refused = [&](const std::string& command, const std::string& named) {
    SCOPED_TRACE(command);
    const Ran r = run(command, dir_);
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find(named), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_FALSE(fs::exists(data));
    for (const auto& e : fs::directory_iterator(dir_))
      EXPECT_NE(e.path().filename().string()[0], '.') << "left over: " << e.path();
  };
  const std::string missing = (dir_ / "no_such_scene.json").string();
  std::string command = train;
  command.replace(command.find(scene_.string()), scene_.string().size(), missing);
  expect_refused(command + out_and_data, missing);
  expect_refused(train + " --vary /fluid_blockz/0/velocity/0=0:1" + out_and_data, "/fluid_blockz");
  expect_refused(train + " --vary fluid_blocks=0:1" + out_and_data, "--vary fluid_blocks=0:1");
  expect_refused(train + " --set-scene /particle_radius=-1" + out_and_data, "/particle_radius");
  expect_refused(train_from_scene("7", "0.5/0.5") + out_and_data, "--split 0.5/0.5");
  expect_refused(train_from_scene("7", "0.5/0/0.5") + out_and_data, "0 validation trajectories");
  expect_refused(train + " --data " + dir_.string() + out_and_data, "--data");
  // Too few frames for a training window: refused before anything is simulated.
  std::string short_frames = train;
  short_frames.replace(short_frames.find(" --frames 9"), 11, " --frames 6");
  expect_refused(short_frames + out_and_data, "--frames 6: a training window needs 7 frames");
  EXPECT_EQ(run(short_frames + out_and_data, dir_).err.find("trajectories:"), std::string::npos);
  const std::string no_source = std::string(SPILL_TRAIN_EXE) + " --config " + SPILL_SOURCE_DIR +
                                "/configs/training/gns_smoke.json --out " + out.string();
  expect_refused(no_source, "--data");
  expect_refused(no_source + " --data " + dir_.string() + " --vary /a=0:1", "--scene");
  // A --save-data folder that exists is never replaced.
  fs::create_directories(data);
  std::ofstream(data / "metadata.json") << "{}";
  const Ran r = run(train + out_and_data, dir_);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("--save-data"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_EQ(read_json(data / "metadata.json"), nlohmann::json::object());
}

// best_checkpoint_trajectories: at every validation the model forecasts the valid trajectory
// standalone and the run keeps the checkpoint whose forecast's oil footprint scored best (FSS at
// 20 cm, 1 s in), saying which in best.json; the score is the checkpoint's own (best.pt reloaded
// scores the same forecast again) and the log's column holds every validation's.
TEST_F(SceneTraining, KeepsTheCheckpointWhoseStandaloneForecastScoredBest) {
  const fs::path out = dir_ / "run", data = dir_ / "data";
  const std::string river = std::string(SPILL_SOURCE_DIR) + "/configs/scenes/river_small.json";
  const Ran r = run(std::string(SPILL_TRAIN_EXE) + " --config " + SPILL_SOURCE_DIR +
                        "/configs/training/dpi_smoke.json --scene " + river +
                        " --trajectories 2 --split 0.5/0.5/0 --seed 3"
                        " --set-scene /leaks/0/start=0.1 --set-scene /leaks/0/duration=0.8"
                        " --set-scene /end_time=1.6 --threads 1 --set /steps=40"
                        " --set /validate_every=10 --set /checkpoint_every=20 --set /log_every=10"
                        " --set /best_checkpoint_trajectories=1 --save-data " +
                        data.string() + " --out " + out.string(),
                    dir_);
  ASSERT_EQ(r.code, 0) << r.err;
  const std::vector<std::string> scores =
      training_log::column(out / "log.csv", "valid_standalone_fss");
  ASSERT_EQ(scores.size(), 4u);  // steps 10, 20, 30, 40
  double best = -1;
  int64_t best_step = 0;
  for (size_t k = 0; k < scores.size(); ++k) {
    ASSERT_FALSE(scores[k].empty()) << "step " << 10 * (k + 1);
    const double s = std::stod(scores[k]);
    EXPECT_GE(s, 0);
    EXPECT_LE(s, 1);
    if (s > best) best = s, best_step = int64_t(10 * (k + 1));
  }
  const nlohmann::json record = read_json(out / "best.json");
  EXPECT_EQ(record.at("step"), best_step);
  EXPECT_NEAR(record.at("valid_standalone_fss").get<double>(), best, 1e-5);  // log: 6 digits
  gnn::LoadedCheckpoint kept = gnn::load_checkpoint((out / "best.pt").string());
  EXPECT_EQ(kept.state.step, best_step);
  kept.simulator->model().eval();
  const gnn::DatasetMetadata metadata = gnn::read_metadata((data / "metadata.json").string());
  const auto valid = gnn::read_split(data.string(), "valid", metadata);
  ASSERT_EQ(valid.size(), 1u);
  EXPECT_NEAR(gnn::standalone_footprint_skill(*kept.simulator, valid[0], metadata),
              record.at("valid_standalone_fss").get<double>(), 1e-9);
}
