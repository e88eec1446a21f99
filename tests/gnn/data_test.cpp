// The learning pipeline's inputs: dataset reader, radius graph, noise and configs.
#include <ATen/CPUGeneratorImpl.h>
#include <gtest/gtest.h>
#include <hdf5.h>

#include <unistd.h>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>

#include "common/config_error.h"
#include "gnn/data/dataset.h"
#include "gnn/data/frame_window.h"
#include "gnn/graph/radius_graph.h"
#include "gnn/models/graph_model.h"
#include "gnn/training/checkpoint.h"
#include "gnn/training/noise.h"
#include "gnn/training/objective.h"
#include "tests/gnn/small_models.h"
#include "tests/gnn/tiny_dataset.h"
#include "train/training_config.h"

namespace fs = std::filesystem;

namespace {
fs::path temp_dir(const std::string& name) {
  fs::path p = fs::temp_directory_path() / ("gnn_test_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

std::set<std::pair<int64_t, int64_t>> edge_set(const gnn::RadiusGraph& g) {
  std::set<std::pair<int64_t, int64_t>> s;
  auto e = g.edge_index.accessor<int64_t, 2>();
  for (int64_t k = 0; k < g.edge_index.size(1); ++k) s.insert({e[0][k], e[1][k]});
  return s;
}
}  // namespace

TEST(Dataset, ReadsBackTheTinyDatasetWithItsShapesAndTypes) {
  const fs::path dir = temp_dir("read");
  tiny::write(dir);
  auto m = gnn::read_metadata((dir / "metadata.json").string());
  auto train = gnn::read_split(dir.string(), "train", m);
  ASSERT_EQ(train.size(), 1u);
  const auto& t = train[0];
  EXPECT_EQ(t.position.sizes(), (std::vector<int64_t>{tiny::kFrames, tiny::kParticles, 3}));
  EXPECT_EQ(t.velocity.sizes(), t.position.sizes());
  EXPECT_EQ(t.active.scalar_type(), torch::kBool);
  EXPECT_EQ(t.particle_type.scalar_type(), torch::kInt64);
  EXPECT_EQ(t.boundary.size(0), 21 * 21);
  EXPECT_EQ(t.active[0].sum().item<int64_t>(), tiny::kParticles - tiny::kEmitted);
  EXPECT_EQ(t.active[tiny::kEmitFrame].sum().item<int64_t>(), tiny::kParticles);
  // Oil is 0.94 x water's density and 4 x its viscosity: features (ratio - 1).
  EXPECT_NEAR(t.material[1][0].item<float>(), -0.06f, 1e-6);
  EXPECT_NEAR(t.material[1][1].item<float>(), 3.0f, 1e-6);
  EXPECT_DOUBLE_EQ(t.sph_seconds_per_frame, 0.01);
  fs::remove_all(dir);
}

TEST(Dataset, AMissingDatasetIsAnErrorNamingTheFileAndGroup) {
  const fs::path dir = temp_dir("missing");
  tiny::write(dir);
  const std::string file = (dir / "valid.h5").string();
  hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  H5Ldelete(f, "/00000/position", H5P_DEFAULT);
  H5Fclose(f);
  auto m = gnn::read_metadata((dir / "metadata.json").string());
  try {
    gnn::read_split(dir.string(), "valid", m);
    FAIL() << "no error";
  } catch (const gnn::DatasetError& e) {
    EXPECT_NE(std::string(e.what()).find(file + ":/00000"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("position"), std::string::npos) << e.what();
  }
  std::ofstream(dir / "test.h5", std::ios::trunc) << "not hdf5";
  EXPECT_THROW(gnn::read_split(dir.string(), "test", m), gnn::DatasetError);
  fs::remove_all(dir);
}

TEST(Dataset, MetadataWithoutStatisticsIsAnError) {
  const fs::path dir = temp_dir("meta");
  tiny::write(dir);
  nlohmann::json m;
  std::ifstream(dir / "metadata.json") >> m;
  m.erase("acc_std");
  std::ofstream(dir / "metadata.json", std::ios::trunc) << m.dump();
  try {
    gnn::read_metadata((dir / "metadata.json").string());
    FAIL() << "no error";
  } catch (const gnn::DatasetError& e) {
    EXPECT_NE(std::string(e.what()).find("acc_std"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

// The optional parts of metadata.json read later (per-trajectory split, timing and parameters,
// materials, particle types) are checked at load: a damaged one names the file and the key
// instead of surfacing as a raw JSON type error.
TEST(Dataset, DamagedOptionalMetadataIsAnErrorNamingTheKey) {
  const fs::path dir = temp_dir("meta_optional");
  tiny::write(dir);
  nlohmann::json original;
  std::ifstream(dir / "metadata.json") >> original;
  const std::vector<std::pair<std::string, nlohmann::json>> damages = {
      {"/trajectories", 3},         {"/particle_types", nlohmann::json::array({0})},
      {"/scene", "river"},          {"/scene/materials", 1},
      {"/trajectories/0/split", 5}, {"/trajectories/1/sph_seconds_per_frame", "fast"}};
  for (const auto& [pointer, value] : damages) {
    nlohmann::json m = original;
    m[nlohmann::json::json_pointer(pointer)] = value;
    std::ofstream(dir / "metadata.json", std::ios::trunc) << m.dump();
    try {
      gnn::read_metadata((dir / "metadata.json").string());
      ADD_FAILURE() << pointer << ": accepted";
    } catch (const common::ConfigError& e) {
      EXPECT_EQ(e.pointer(), pointer) << e.what();
      EXPECT_EQ(e.file(), (dir / "metadata.json").string());
    }
  }
  fs::remove_all(dir);
}

// Replaces dataset `name` of group 00000 in `file` by one of `dims` floats holding `value`;
// with `unwritten` its chunks are never written (a header that claims more than the file stores).
void replace_dataset(const fs::path& file, const char* name, std::vector<hsize_t> dims, float value,
                     bool unwritten) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  const hid_t g = H5Gopen2(f, "00000", H5P_DEFAULT);
  H5Ldelete(g, name, H5P_DEFAULT);
  const hid_t space = H5Screate_simple(int(dims.size()), dims.data(), nullptr);
  const hid_t props = H5Pcreate(H5P_DATASET_CREATE);
  std::vector<hsize_t> chunk(dims.size(), 1);
  H5Pset_chunk(props, int(dims.size()), chunk.data());
  const hid_t d = H5Dcreate2(g, name, H5T_NATIVE_FLOAT, space, H5P_DEFAULT, props, H5P_DEFAULT);
  if (!unwritten) {
    hsize_t n = 1;
    for (hsize_t k : dims) n *= k;
    std::vector<float> values(n, value);
    H5Dwrite(d, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
  }
  H5Dclose(d);
  H5Pclose(props);
  H5Sclose(space);
  H5Gclose(g);
  H5Fclose(f);
}

// What the data fuzzer reached through flipped bytes: boundary positions at 1e30 (the radius
// graph's neighbour grid then had "too many cells", exit 1) and a header claiming a huge shape
// (the allocator failed, exit 1). Both are refused at load, naming the file and the dataset.
TEST(Dataset, AbsurdBoundaryPositionsAndClaimedShapesAreRefusedAtLoad) {
  const fs::path dir = temp_dir("absurd");
  tiny::write(dir);
  const auto m = gnn::read_metadata((dir / "metadata.json").string());
  replace_dataset(dir / "valid.h5", "boundary_position", {1, 3}, 1e30f, false);
  try {
    gnn::read_split(dir.string(), "valid", m);
    ADD_FAILURE() << "accepted";
  } catch (const gnn::DatasetError& e) {
    EXPECT_NE(std::string(e.what()).find("valid.h5:/00000/boundary_position"), std::string::npos)
        << e.what();
  }
  replace_dataset(dir / "test.h5", "time", {1000000000}, 0, true);
  try {
    gnn::read_split(dir.string(), "test", m);
    ADD_FAILURE() << "accepted";
  } catch (const gnn::DatasetError& e) {
    EXPECT_NE(std::string(e.what()).find("test.h5:/00000/time: claims shape [1000000000]"),
              std::string::npos)
        << e.what();
  }
  fs::remove_all(dir);
}

TEST(FrameWindow, EmittedParticlesGetAHistoryAlongTheirLaunchVelocity) {
  const fs::path dir = temp_dir("window");
  tiny::write(dir);
  auto m = gnn::read_metadata((dir / "metadata.json").string());
  auto t = gnn::read_split(dir.string(), "train", m)[0];
  const int64_t p = tiny::kParticles - 1, frame = tiny::kEmitFrame + 2;
  auto h = gnn::position_history(t, frame, torch::tensor({p}), tiny::kFrameDt)[0];
  // Recorded positions from the emission frame on, extrapolated before it.
  EXPECT_TRUE(torch::equal(h[5], t.position[frame][p]));
  EXPECT_TRUE(torch::equal(h[3], t.position[tiny::kEmitFrame][p]));
  auto step = t.velocity[tiny::kEmitFrame][p] * float(tiny::kFrameDt);
  EXPECT_TRUE(torch::allclose(h[2], t.position[tiny::kEmitFrame][p] - step, 0, 1e-6));
  EXPECT_TRUE(torch::allclose(h[0], t.position[tiny::kEmitFrame][p] - 3 * step, 0, 1e-6));
  fs::remove_all(dir);
}

TEST(RadiusGraph, GridEqualsBruteForce) {
  torch::manual_seed(3);
  for (double radius : {0.08, 0.15}) {
    auto fluid = torch::rand({1000, 3});
    auto boundary = torch::rand({300, 3}) * torch::tensor({1.4f, 1.4f, 0.2f}) - 0.2f;
    auto grid = gnn::build_radius_graph(fluid, boundary, radius);
    auto brute = gnn::brute_force_radius_graph(fluid, boundary, radius);
    EXPECT_TRUE(torch::equal(grid.boundary_nodes, brute.boundary_nodes));
    EXPECT_GT(grid.boundary_nodes.size(0), 0);
    EXPECT_LT(grid.boundary_nodes.size(0), 300);
    const auto grid_edges = edge_set(grid), brute_edges = edge_set(brute);
    EXPECT_GT(grid_edges.size(), 1000u);
    // The same edge set both ways: every grid edge is a brute-force edge and every brute-force
    // edge a grid edge (counted, so a failure says how many and in which direction).
    long missing = 0, extra = 0;
    for (const auto& edge : brute_edges) missing += !grid_edges.count(edge);
    for (const auto& edge : grid_edges) extra += !brute_edges.count(edge);
    EXPECT_EQ(missing, 0) << "brute-force edges the grid lacks, radius " << radius;
    EXPECT_EQ(extra, 0) << "grid edges brute force lacks, radius " << radius;
    // Every edge has its reverse, none is a self-loop or joins two boundary nodes, none repeats.
    long unreversed = 0, self_loops = 0, boundary_pairs = 0;
    for (const auto& [s, r] : grid_edges) {
      unreversed += !grid_edges.count({r, s});
      self_loops += s == r;
      boundary_pairs += s >= 1000 && r >= 1000;
    }
    EXPECT_EQ(unreversed, 0) << "edges without their reverse, radius " << radius;
    EXPECT_EQ(self_loops, 0);
    EXPECT_EQ(boundary_pairs, 0);
    EXPECT_EQ(grid_edges.size(), size_t(grid.edge_index.size(1))) << "repeated edges";
  }
}

TEST(Noise, RandomWalkHasTheStatedStatistics) {
  const double noise_std = 0.01;
  auto history = torch::zeros({20000, 6, 3});
  auto generator = at::make_generator<at::CPUGeneratorImpl>(5);
  auto noisy = gnn::random_walk_noise(history, noise_std, generator);
  auto velocity = noisy.slice(1, 1) - noisy.slice(1, 0, 5);  // [n, 5, 3]
  auto increments = velocity.slice(1, 1) - velocity.slice(1, 0, 4);
  // Each velocity step gets std noise_std / sqrt(5); the last velocity is off by noise_std.
  EXPECT_NEAR(increments.std().item<double>(), noise_std / std::sqrt(5.0),
              0.03 * noise_std / std::sqrt(5.0));
  EXPECT_NEAR(velocity.select(1, 4).std().item<double>(), noise_std, 0.03 * noise_std);
  EXPECT_NEAR(velocity.select(1, 0).std().item<double>(), noise_std / std::sqrt(5.0),
              0.03 * noise_std / std::sqrt(5.0));
  EXPECT_EQ(noisy.select(1, 0).abs().max().item<double>(), 0.0);
}

// GNS's target under noise, computed here from its definition: the true next velocity
// (next - x_t, from the clean window) less the noisy window's last velocity. A model that meets
// it corrects the velocity noise and keeps the position's offset.
TEST(Noise, TargetCorrectsTheVelocityNoiseAsGnsDefinesIt) {
  auto generator = at::make_generator<at::CPUGeneratorImpl>(9);
  const auto clean = torch::randn({500, 6, 3}) * 0.1;
  const auto noisy = gnn::random_walk_noise(clean, 0.01, generator);
  const auto next = torch::randn({500, 3}) * 0.1;
  const auto a = gnn::noisy_target_acceleration(clean, noisy, next);
  const auto true_velocity = next - clean.select(1, 5);
  const auto noisy_velocity = noisy.select(1, 5) - noisy.select(1, 4);
  EXPECT_TRUE(torch::allclose(a, true_velocity - noisy_velocity, 0, 1e-6));
  // Stepped from the noisy state, the prediction lands at next plus the last position's noise.
  const auto landed = noisy.select(1, 5) + noisy_velocity + a;
  EXPECT_TRUE(torch::allclose(landed, next + (noisy.select(1, 5) - clean.select(1, 5)), 0, 1e-6));
  EXPECT_GT((landed - next).abs().max().item<float>(), 1e-3);  // the noise is not undone
  // Without noise it is the plain target.
  EXPECT_TRUE(torch::allclose(gnn::noisy_target_acceleration(clean, clean, next),
                              gnn::target_acceleration(clean, next), 0, 0));
}

TEST(Configs, EveryShippedModelAndTrainingConfigLoads) {
  const fs::path root = SPILL_SOURCE_DIR;
  int count = 0;
  for (const auto& e : fs::directory_iterator(root / "configs/models")) {
    auto j = nlohmann::json::parse(std::ifstream(e.path()));
    EXPECT_NO_THROW(gnn::make_model(j, e.path().string())) << e.path();
    ++count;
  }
  for (const auto& e : fs::directory_iterator(root / "configs/training")) {
    EXPECT_NO_THROW(train::load_training_config(e.path().string(), {})) << e.path();
    ++count;
  }
  EXPECT_GE(count, 3);
}

// --resume compares the asked config with the stored one: a run made before a key existed (its
// stored config lacks the key, or a whole objective's section) is not refused for it while the
// key keeps its default, which is what that run trained with; any other value, or a changed key,
// is named; /steps may change.
TEST(Configs, AResumedRunMadeBeforeANewKeyIsRefusedOnlyForAChangedValue) {
  const fs::path root = SPILL_SOURCE_DIR;
  const auto asked =
      train::load_training_config((root / "configs/training/gns_smoke.json").string(), {})
          .training_json;
  auto stored = asked;
  stored["pagat"].erase("attention_loss_weight");
  stored["pagat"].erase("distillation_stride");
  stored.erase("acceleration_mse");
  EXPECT_TRUE(train::keys_that_differ(stored, asked).empty());
  auto changed = asked;
  changed["pagat"]["attention_loss_weight"] = 0.5;
  changed["acceleration_mse"]["oil_fraction_loss_weight"] = 0.5;
  changed["steps"] = 99999;
  auto differ = train::keys_that_differ(stored, changed);
  std::sort(differ.begin(), differ.end());
  EXPECT_EQ(differ, (std::vector<std::string>{"/acceleration_mse/oil_fraction_loss_weight",
                                              "/pagat/attention_loss_weight"}));
  changed = asked;
  changed["lr_max"] = 0.5;
  EXPECT_EQ(train::keys_that_differ(stored, changed), std::vector<std::string>{"/lr_max"});
}

// Runs and checkpoints made before the objectives had sections store their keys flat, as the
// committed docs/results checkpoints do (the baselines from before PAGATNet's keys existed, the
// teacher from before generator_until): each compares equal with the shipped config it was
// trained with, and a changed objective setting is named by its section's pointer.
TEST(Configs, CommittedCheckpointsWithFlatKeysCompareEqualToTheirShippedConfigs) {
  const fs::path root = SPILL_SOURCE_DIR;
  const std::vector<std::pair<std::string, std::string>> runs = {
      {"baselines/gns.pt", "gns_river_small.json"},
      {"baselines/dpi.pt", "dpi_river_small.json"},
      {"pagat/teacher.pt", "pagat_teacher_river_small.json"},
      {"pagat/student_light_distillation.pt", "pagat_student_light_distillation_river_small.json"}};
  for (const auto& [checkpoint, config] : runs) {
    SCOPED_TRACE(checkpoint);
    const nlohmann::json stored =
        gnn::load_checkpoint((root / "docs/results" / checkpoint).string()).state.training_config;
    ASSERT_TRUE(stored.contains("oil_fraction_loss_weight")) << "not a flat-key config";
    const std::string file = (root / "configs/training" / config).string();
    EXPECT_TRUE(train::keys_that_differ(stored, train::load_training_config(file, {}).training_json)
                    .empty());
    EXPECT_EQ(train::keys_that_differ(
                  stored,
                  train::load_training_config(file, {"/pagat/distillation_beta=2"}).training_json),
              std::vector<std::string>{"/pagat/distillation_beta"});
  }
}

// The objectives' keys that configs held flat before their sections are read into them, from a
// file or an override; given both ways, the flat key is named.
TEST(Configs, FlatObjectiveKeysAreReadIntoTheirSections) {
  const fs::path root = SPILL_SOURCE_DIR;
  const std::string file = (root / "configs/training/pagat_smoke.json").string();
  const auto j = train::load_training_config(
                     file, {"/attention_loss_weight=0.3", "/oil_fraction_loss_weight=0"})
                     .training_json;
  EXPECT_EQ(j.at("pagat").at("attention_loss_weight"), 0.3);
  EXPECT_EQ(j.at("acceleration_mse").at("oil_fraction_loss_weight"), 0.0);
  EXPECT_FALSE(j.contains("attention_loss_weight"));
  try {
    train::load_training_config(file,
                                {"/attention_loss_weight=0.3", "/pagat/attention_loss_weight=0.2"});
    ADD_FAILURE() << "accepted";
  } catch (const common::ConfigError& e) {
    EXPECT_EQ(e.file(), file);
    EXPECT_EQ(e.pointer(), "/attention_loss_weight");
    EXPECT_NE(std::string(e.what()).find("/pagat/attention_loss_weight"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(train::load_training_config(file, {"/pagat/attention_loss_weight=-1"}),
               common::ConfigError);
  EXPECT_THROW(train::load_training_config(file, {"/pagat/attention_los_weight=1"}),
               common::ConfigError);
}

// Every registered objective's settings are part of the training config: in its reference, in
// the resolved config (defaults filled in) and validated under their section (the registry
// enumerated, so a new objective's keys are checked as they are added).
TEST(Configs, EveryObjectivesSettingsAreInTheTrainingConfigAndItsReference) {
  const fs::path root = SPILL_SOURCE_DIR;
  const std::string file = (root / "configs/training/gns_smoke.json").string();
  const std::string reference = train::training_config_reference_markdown();
  const auto resolved = train::load_training_config(file, {}).training_json;
  int keys = 0;
  for (const auto& objective : gnn::objective_entries()) {
    ASSERT_FALSE(objective.sections.empty()) << objective.name;
    for (const auto& section : objective.sections) {
      const nlohmann::json defaults = section.make_default()->write();
      EXPECT_EQ(resolved.at(section.key), defaults) << section.key;
      for (auto it = defaults.begin(); it != defaults.end(); ++it) {
        const std::string pointer = "/" + section.key + "/" + it.key();
        EXPECT_NE(reference.find("`" + pointer + "`"), std::string::npos) << pointer;
        EXPECT_THROW(train::load_training_config(file, {pointer + "=[]"}), common::ConfigError)
            << pointer;
        ++keys;
      }
    }
    EXPECT_THROW(
        train::load_training_config(file, {"/" + objective.sections[0].key + "/no_such=1"}),
        common::ConfigError);
  }
  EXPECT_GE(keys, 8);
}

TEST(Configs, AnUnknownKeyIsAnErrorNamingFileAndKey) {
  const fs::path root = SPILL_SOURCE_DIR;
  const std::string file = (root / "configs/training/gns_smoke.json").string();
  try {
    train::load_training_config(file, {"/learning_rate=0.1"});
    FAIL() << "no error";
  } catch (const common::ConfigError& e) {
    EXPECT_EQ(e.file(), file);
    EXPECT_EQ(e.pointer(), "/learning_rate");
  }
  try {
    train::load_training_config(file, {"/model/latnet=3"});
    FAIL() << "no error";
  } catch (const common::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("/latnet"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("gns.json"), std::string::npos) << e.what();
  }
  EXPECT_THROW(train::load_training_config(file, {"/steps=-3"}), common::ConfigError);
  EXPECT_THROW(gnn::make_model({{"model", "pagatnet"}}, "x.json"), common::ConfigError);
}

// DPI-Nets and the constant-velocity floor validate their configs as GNS does: an unknown key, a
// wrong type and a value out of range each name the file and the key.
TEST(Configs, DpiAndConstantVelocityBadKeysNameFileAndKey) {
  const fs::path root = SPILL_SOURCE_DIR;
  struct Case {
    std::string file, pointer;
    nlohmann::json value;
    std::string says;
  };
  const std::vector<Case> cases = {
      {"dpi.json", "/propagation_stepz", 3, "unknown key"},
      {"dpi.json", "/propagation_steps", "three", "expected an integer"},
      {"dpi.json", "/propagation_steps", 0, "expected >= 1"},
      {"dpi.json", "/relation_width", 2.5, "expected an integer"},
      {"dpi.json", "/particle_width", -200, "expected >= 1"},
      {"dpi.json", "/radius", 0, "expected > 0"},
      {"dpi.json", "/noise_std", "none", "expected a number"},
      {"constant_velocity.json", "/latent", 16, "unknown key"},
      {"constant_velocity.json", "/noise_std", -1e-4, "expected >= 0"}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.file + ":" + c.pointer);
    const std::string file = (root / "configs/models" / c.file).string();
    auto j = nlohmann::json::parse(std::ifstream(file));
    j[nlohmann::json::json_pointer(c.pointer)] = c.value;
    try {
      gnn::make_model(j, file);
      ADD_FAILURE() << "accepted";
    } catch (const common::ConfigError& e) {
      EXPECT_EQ(e.file(), file);
      EXPECT_EQ(e.pointer(), c.pointer);
      EXPECT_NE(std::string(e.what()).find(c.says), std::string::npos) << e.what();
    }
  }
  // Training-config overrides reach the model's keys with the model file named.
  try {
    train::load_training_config((root / "configs/training/dpi_smoke.json").string(),
                                {"/model/effect_widht=8"});
    ADD_FAILURE() << "accepted";
  } catch (const common::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("/effect_widht"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("dpi.json"), std::string::npos) << e.what();
  }
}

// Every registered model reads the shared input section (gnn/models/model_input_config.h): its
// radius and noise are validated under their keys (the registry enumerated).
TEST(Configs, EveryModelValidatesTheSharedInputKeys) {
  for (const std::string& name : gnn::model_names()) {
    SCOPED_TRACE(name);
    const auto config = small_models::config(name);
    for (const auto& [key, value] :
         std::vector<std::pair<std::string, double>>{{"radius", 0.0}, {"noise_std", -1e-4}}) {
      auto bad = config;
      bad[key] = value;
      try {
        gnn::make_model(bad, name + ".json");
        ADD_FAILURE() << key << " accepted";
      } catch (const common::ConfigError& e) {
        EXPECT_EQ(e.pointer(), "/" + key);
      }
    }
    auto model_config = gnn::make_model(config, name + ".json")->config();
    EXPECT_TRUE(model_config.contains("radius") && model_config.contains("noise_std"));
  }
}

TEST(Schedule, LearningRateDecaysFromMaxToMin) {
  train::TrainingConfig c;
  EXPECT_DOUBLE_EQ(train::learning_rate(c, 0), 1e-4);
  EXPECT_NEAR(train::learning_rate(c, c.decay_steps), (1e-4 - 1e-6) * 0.1 + 1e-6, 1e-15);
  EXPECT_NEAR(train::learning_rate(c, 100 * int64_t(c.decay_steps)), 1e-6, 1e-12);
}
