// `spill-sim generate`: a dataset has the promised splits, shapes, types and statistics (checked
// against the written positions), an interrupted generation resumes without redoing finished
// trajectories and ends identical to an uninterrupted one, the same seed gives the same data on
// one thread, and bad requests are clear errors.

#include "sph/generation/dataset_folder.h"
#include "sph/generation/generation.h"

#include <gtest/gtest.h>
#include <hdf5.h>
#include <omp.h>

#include <filesystem>
#include <fstream>

#include "sph/app/scene_runner.h"
#include "sph/core/config.h"

namespace sph {
namespace {

namespace fs = std::filesystem;

// One scene file per test: ctest runs tests side by side, and a shared file could be read while
// another test rewrites it.
fs::path tiny_scene(const std::string& name) {
  const fs::path file = fs::temp_directory_path() / (name + "_tiny.json");
  std::ofstream(file) << R"({
    "name": "tiny", "particle_radius": 0.02, "end_time": 0.2, "output": {"frame_dt": 0.02},
    "boxes": [{"min": [0, 0, 0], "max": [0.4, 0.4, 0.4]}],
    "fluid_blocks": [{"min": [0, 0, 0], "max": [0.2, 0.2, 0.2], "velocity": [0, 0, 0]}]})";
  return file;
}

GenerateOptions options(const std::string& dir) {
  GenerateOptions o;
  o.scene_file = tiny_scene(dir).string();
  o.trajectories = 3;
  o.out_dir = fs::temp_directory_path() / dir;
  o.vary = {parse_parameter_range("/fluid_blocks/0/velocity/0=0:1")};
  o.seed = 7;
  o.split = {0.34, 0.33, 0.33};
  o.frames = 6;
  return o;
}

nlohmann::json read_json(const fs::path& file) {
  std::ifstream in(file);
  return nlohmann::json::parse(in);
}

// position of group `group` in `file`, with its shape.
std::vector<float> read_positions(const fs::path& file, const std::string& group,
                                  std::vector<hsize_t>* dims) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  EXPECT_GE(f, 0) << file;
  const hid_t ds = H5Dopen2(f, (group + "/position").c_str(), H5P_DEFAULT);
  const hid_t space = H5Dget_space(ds);
  dims->assign(3, 0);
  H5Sget_simple_extent_dims(space, dims->data(), nullptr);
  const hid_t type = H5Dget_type(ds);
  EXPECT_EQ(H5Tget_class(type), H5T_FLOAT);
  EXPECT_EQ(H5Tget_size(type), 4u);
  std::vector<float> data(size_t((*dims)[0] * (*dims)[1] * (*dims)[2]));
  H5Dread(ds, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data());
  H5Tclose(type);
  H5Sclose(space);
  H5Dclose(ds);
  H5Fclose(f);
  return data;
}

class Generate : public ::testing::Test {
 protected:
  void SetUp() override {
    threads_ = omp_get_max_threads();
    omp_set_num_threads(1);  // bit-reproducible
  }
  void TearDown() override { omp_set_num_threads(threads_); }
  int threads_ = 1;
};

TEST_F(Generate, WritesSplitsShapesAndTheTrainingStatistics) {
  GenerateOptions o = options("spill_generate_a");
  fs::remove_all(o.out_dir);
  const nlohmann::json meta = generate_dataset(o).metadata;
  EXPECT_EQ(meta.at("counts"), (nlohmann::json{{"train", 1}, {"valid", 1}, {"test", 1}}));
  EXPECT_EQ(meta.at("sequence_length"), 6);
  EXPECT_EQ(meta.at("particle_types"), (nlohmann::json{{"water", 0}, {"oil", 1}, {"boundary", 2}}));
  EXPECT_TRUE(meta.contains("default_connectivity_radius"));
  ASSERT_EQ(meta.at("trajectories").size(), 3u);
  for (const auto& t : meta.at("trajectories")) {
    const double v = t.at("parameters").at("/fluid_blocks/0/velocity/0");
    EXPECT_GE(v, 0);
    EXPECT_LE(v, 1);
  }
  // The statistics, recomputed from the training file's positions.
  std::vector<hsize_t> dims;
  const std::vector<float> x = read_positions(o.out_dir / "train.h5", "00000", &dims);
  ASSERT_EQ(dims, (std::vector<hsize_t>{6, 125, 3}));
  auto at = [&](size_t t, size_t i, size_t k) { return double(x[(t * dims[1] + i) * 3 + k]); };
  double v_sum = 0, a_sum = 0, v_n = 0, a_n = 0;
  for (size_t t = 1; t < dims[0]; ++t)
    for (size_t i = 0; i < dims[1]; ++i) {
      v_sum += at(t, i, 0) - at(t - 1, i, 0), ++v_n;
      if (t + 1 < dims[0]) a_sum += at(t + 1, i, 0) - 2 * at(t, i, 0) + at(t - 1, i, 0), ++a_n;
    }
  EXPECT_NEAR(meta["vel_mean"][0].get<double>(), v_sum / v_n, 1e-9);
  EXPECT_NEAR(meta["acc_mean"][0].get<double>(), a_sum / a_n, 1e-9);
  EXPECT_GT(meta["vel_std"][2].get<double>(), 0);
  EXPECT_EQ(read_json(o.out_dir / "metadata.json"), meta);
}

TEST_F(Generate, ResumesWithoutRedoingAndMatchesAnUninterruptedRun) {
  GenerateOptions whole = options("spill_generate_whole");
  fs::remove_all(whole.out_dir);
  const nlohmann::json expected = generate_dataset(whole).metadata;

  GenerateOptions o = options("spill_generate_resume");
  fs::remove_all(o.out_dir);
  // A generation interrupted after its first trajectory: generate, then remove what came after
  // the first trajectory, then run again with the stop flag raised, which interrupts the second
  // trajectory and must leave nothing of it behind.
  generate_dataset(o);
  for (int k : {1, 2}) {
    fs::remove(o.out_dir / "parts" / ("trajectory_0000" + std::to_string(k) + ".h5"));
    fs::remove(o.out_dir / "parts" / ("trajectory_0000" + std::to_string(k) + ".json"));
  }
  for (const char* f : {"train.h5", "valid.h5", "test.h5", "metadata.json"})
    fs::remove(o.out_dir / f);
  std::atomic<bool> stop{true};
  GenerateOptions stopped = o;
  stopped.stop = &stop;
  EXPECT_THROW(generate_dataset(stopped), RunInterrupted);
  EXPECT_FALSE(fs::exists(o.out_dir / "parts" / "trajectory_00001.h5.tmp"));
  EXPECT_FALSE(fs::exists(o.out_dir / "parts" / "trajectory_00001.h5"));
  EXPECT_FALSE(fs::exists(o.out_dir / "metadata.json"));

  const auto kept = fs::last_write_time(o.out_dir / "parts" / "trajectory_00000.h5");
  const nlohmann::json resumed = generate_dataset(o).metadata;
  EXPECT_EQ(fs::last_write_time(o.out_dir / "parts" / "trajectory_00000.h5"), kept);
  EXPECT_EQ(resumed.at("vel_mean"), expected.at("vel_mean"));
  EXPECT_EQ(resumed.at("acc_std"), expected.at("acc_std"));
  for (const char* split : {"train.h5", "valid.h5", "test.h5"}) {
    std::vector<hsize_t> d1, d2;
    EXPECT_EQ(read_positions(o.out_dir / split, "00000", &d1),
              read_positions(whole.out_dir / split, "00000", &d2))
        << split;
  }
  // Another request in the same folder is refused rather than mixed in, naming what differs:
  // the seed, the frames, a --set (once only the drawn values were compared, so these reused
  // the old trajectories and rewrote metadata.json, exit 0).
  auto expect_refused = [&](GenerateOptions changed, const std::string& key) {
    try {
      generate_dataset(changed);
      ADD_FAILURE() << key << ": the changed request was accepted";
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("request.json"), std::string::npos) << e.what();
    }
  };
  GenerateOptions changed = o;
  changed.seed = 8;
  expect_refused(changed, "/seed");
  changed = o;
  changed.frames = o.frames + 1;
  expect_refused(changed, "/frames");
  changed = o;
  changed.overrides.push_back("/particle_radius=0.021");
  expect_refused(changed, "/scene/particle_radius");
  EXPECT_EQ(read_json(o.out_dir / "metadata.json"), resumed) << "the dataset is untouched";
  // A damaged part description is named with its key (it was a raw JSON type error).
  const fs::path part = o.out_dir / "parts" / "trajectory_00001.json";
  nlohmann::json damaged = read_json(part);
  damaged["acceleration_moments"]["sum"] = {1, 2};
  std::ofstream(part, std::ios::trunc) << damaged.dump();
  try {
    generate_dataset(o);
    ADD_FAILURE() << "a damaged part was accepted";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.file(), part.string());
    EXPECT_EQ(e.pointer(), "/acceleration_moments/sum");
  }
  std::ofstream(part, std::ios::trunc) << "{\"parameters\": ";  // truncated
  EXPECT_THROW(generate_dataset(o), ConfigError);
}

// A finished part is assembled only when it is the one this generation wrote. Copied from a
// dataset of another particle radius (and so another particle count), the part file alone, or
// with its description, is refused naming the part; the finished dataset is left as it was.
TEST_F(Generate, RefusesAPartOfAnotherDataset) {
  GenerateOptions o = options("spill_generate_own");
  fs::remove_all(o.out_dir);
  const nlohmann::json own = generate_dataset(o).metadata;
  GenerateOptions other = options("spill_generate_other");
  other.overrides = {"/particle_radius=0.025"};
  fs::remove_all(other.out_dir);
  generate_dataset(other);
  const fs::path parts = o.out_dir / "parts", foreign = other.out_dir / "parts";
  const std::string valid_before = read_json(o.out_dir / "metadata.json").dump();
  auto expect_refused = [&](const fs::path& named, const std::string& pointer,
                            const std::string& words) {
    try {
      generate_dataset(o);
      ADD_FAILURE() << "a foreign part was assembled";
    } catch (const ConfigError& e) {
      EXPECT_EQ(e.file(), named.string()) << e.what();
      EXPECT_EQ(e.pointer(), pointer) << e.what();
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
    EXPECT_EQ(read_json(o.out_dir / "metadata.json").dump(), valid_before);
  };
  // The part file alone: its bytes are not those its description recorded.
  fs::copy_file(parts / "trajectory_00001.h5", o.out_dir / "kept.h5");
  fs::copy_file(foreign / "trajectory_00001.h5", parts / "trajectory_00001.h5",
                fs::copy_options::overwrite_existing);
  expect_refused(parts / "trajectory_00001.h5", "/00000", "another dataset");
  // The same from a description without the record (as parts were written before it): the
  // part's particle count is not the one described.
  nlohmann::json unrecorded = read_json(parts / "trajectory_00001.json");
  unrecorded.erase("part");
  std::ofstream(parts / "trajectory_00001.json", std::ios::trunc) << unrecorded.dump();
  expect_refused(parts / "trajectory_00001.h5", "/00000/position", "particles");
  // The part with its description (the same draws, another radius): another request made it.
  for (const char* f : {"trajectory_00001.h5", "trajectory_00001.json"})
    fs::copy_file(foreign / f, parts / f, fs::copy_options::overwrite_existing);
  expect_refused(parts / "trajectory_00001.json", "/part/request", "another generation request");
  // Its own part back: the dataset assembles as before.
  fs::copy_file(o.out_dir / "kept.h5", parts / "trajectory_00001.h5",
                fs::copy_options::overwrite_existing);
  std::ofstream(parts / "trajectory_00001.json", std::ios::trunc) << unrecorded.dump();
  EXPECT_EQ(generate_dataset(o).metadata, own);
}

// A request cut into shards (a cluster's job array) ends as the same dataset as one process's
// run: each shard simulates only its own trajectories, assembling refuses while any is missing
// and names it, whichever shard finishes the last trajectory assembles, and the statistics and
// the split files do not depend on the cut.
TEST_F(Generate, ShardsAssembleTheDatasetOfOneRun) {
  GenerateOptions whole = options("spill_generate_unsharded");
  fs::remove_all(whole.out_dir);
  const nlohmann::json expected = generate_dataset(whole).metadata;

  GenerateOptions o = options("spill_generate_shards");
  fs::remove_all(o.out_dir);
  o.shard = parse_shard("1/2");
  const GenerationResult first = generate_dataset(o);
  EXPECT_TRUE(first.metadata.is_null());
  EXPECT_EQ(first.simulated, 1);
  EXPECT_EQ(first.missing, (std::vector<int>{0, 2}));
  EXPECT_TRUE(fs::exists(o.out_dir / "parts" / "trajectory_00001.h5"));
  EXPECT_FALSE(fs::exists(o.out_dir / "parts" / "trajectory_00000.h5"));
  EXPECT_FALSE(fs::exists(o.out_dir / "train.h5"));
  EXPECT_FALSE(fs::exists(o.out_dir / "metadata.json"));
  try {
    generate_dataset(stored_generation(o.out_dir));
    ADD_FAILURE() << "assembled with two trajectories missing";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("00000, 00002"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(o.out_dir / "metadata.json"));

  o.shard = parse_shard("0/2");
  const GenerationResult last = generate_dataset(o);
  EXPECT_EQ(last.simulated, 2);
  EXPECT_TRUE(last.missing.empty());
  ASSERT_FALSE(last.metadata.is_null());
  for (const char* key :
       {"vel_mean", "vel_std", "acc_mean", "acc_std", "counts", "sequence_lengths", "generation"})
    EXPECT_EQ(last.metadata.at(key), expected.at(key)) << key;
  // Each trajectory's description, all but its wall times.
  auto untimed = [](nlohmann::json trajectories) {
    for (auto& t : trajectories) t.erase("sph_seconds_per_frame"), t.erase("sph_wall_s");
    return trajectories;
  };
  EXPECT_EQ(untimed(last.metadata.at("trajectories")), untimed(expected.at("trajectories")));
  for (const char* split : {"train.h5", "valid.h5", "test.h5"}) {
    std::vector<hsize_t> d1, d2;
    EXPECT_EQ(read_positions(o.out_dir / split, "00000", &d1),
              read_positions(whole.out_dir / split, "00000", &d2))
        << split;
  }
  EXPECT_EQ(read_json(o.out_dir / "metadata.json"), last.metadata);
  // Assembling again from the folder alone gives the same metadata and leaves no temporaries.
  fs::remove(o.out_dir / "metadata.json");
  fs::remove(o.out_dir / "train.h5");
  const GenerationResult assembled = generate_dataset(stored_generation(o.out_dir));
  EXPECT_EQ(assembled.simulated, 0);
  EXPECT_EQ(assembled.metadata, last.metadata);
  EXPECT_TRUE(fs::exists(o.out_dir / "train.h5"));
  for (const auto& e : fs::directory_iterator(o.out_dir))
    EXPECT_EQ(e.path().string().find(".tmp"), std::string::npos) << e.path();

  EXPECT_THROW(parse_shard("2/2"), common::InputError);
  EXPECT_THROW(parse_shard("-1/2"), common::InputError);
  EXPECT_THROW(parse_shard("1"), common::InputError);
  EXPECT_THROW(parse_shard("1/0"), common::InputError);
  EXPECT_THROW(stored_generation(fs::temp_directory_path() / "spill_generate_nowhere"),
               ConfigError);
}

TEST(GenerateInput, BadRequestsAreClearErrors) {
  EXPECT_THROW(parse_parameter_range("/flow/speed=1.2"), common::InputError);
  EXPECT_THROW(parse_parameter_range("flow/speed=1:2"), common::InputError);
  EXPECT_THROW(parse_parameter_range("/flow/speed=2:1"), common::InputError);
  EXPECT_THROW(parse_parameter_range("/flow/speed=a:1"), common::InputError);
  const ParameterRange r = parse_parameter_range("/flow/speed=1.2:1.8");
  EXPECT_EQ(r.pointer, "/flow/speed");
  EXPECT_DOUBLE_EQ(r.lo, 1.2);
  EXPECT_DOUBLE_EQ(r.hi, 1.8);
  EXPECT_EQ(split_counts(20, {0.8, 0.1, 0.1}), (std::array<int, 3>{16, 2, 2}));
  EXPECT_EQ(split_counts(3, {0.8, 0.1, 0.1}), (std::array<int, 3>{1, 1, 1}));
  EXPECT_EQ(split_counts(4, {1, 0, 0}), (std::array<int, 3>{4, 0, 0}));
  EXPECT_THROW(split_counts(2, {0.8, 0.1, 0.1}), common::InputError);
  EXPECT_THROW(split_counts(10, {0.5, 0.1, 0.1}), common::InputError);
  GenerateOptions o = options("spill_generate_bad");
  o.vary = {parse_parameter_range("/no_such_key=0:1")};
  EXPECT_THROW(generate_dataset(o), ConfigError);
}

}  // namespace
}  // namespace sph
