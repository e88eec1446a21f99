// Models, checkpoints, rollout and the training loop, on the tiny dataset.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <sstream>
#include <tuple>

#include "common/config_error.h"
#include "gnn/data/frame_window.h"
#include "gnn/eval/rollout.h"
#include "gnn/graph/heterogeneous_typing.h"
#include "gnn/graph/radius_graph.h"
#include "gnn/graph/segment_ops.h"
#include "gnn/models/dpi_model.h"
#include "gnn/models/gns_model.h"
#include "gnn/models/model_registry.h"
#include "gnn/runtime/runtime.h"
#include "gnn/training/checkpoint.h"
#include "sph/io/tensor_recorder.h"
#include "sph/scene/scene_loader.h"
#include "sph/simulation/simulation.h"
#include "tests/gnn/small_models.h"
#include "tests/gnn/tiny_dataset.h"
#include "tests/gnn/training_log.h"
#include "train/trainer.h"

namespace fs = std::filesystem;

namespace {

fs::path temp_dir(const std::string& name) {
  fs::path p = fs::temp_directory_path() / ("gnn_model_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

const std::string kSmoke = std::string(SPILL_SOURCE_DIR) + "/configs/training/gns_smoke.json";
const std::string kDpiSmoke = std::string(SPILL_SOURCE_DIR) + "/configs/training/dpi_smoke.json";
const nlohmann::json kSmallDpi = small_models::config("dpi");
const nlohmann::json kConstantVelocity = small_models::config("constant_velocity");
const std::string kPagatSmoke =
    std::string(SPILL_SOURCE_DIR) + "/configs/training/pagat_smoke.json";
const nlohmann::json kSmallPagat = small_models::config("pagat");

struct Tiny {
  fs::path dir;
  gnn::DatasetMetadata metadata;
  gnn::Trajectory trajectory;
  explicit Tiny(const std::string& name) : dir(temp_dir(name)) {
    tiny::write(dir);
    metadata = gnn::read_metadata((dir / "metadata.json").string());
    trajectory = gnn::read_split(dir.string(), "test", metadata)[0];
  }
  ~Tiny() { fs::remove_all(dir); }
  // A small GNS unless `config` names another model.
  std::unique_ptr<gnn::LearnedSimulator> simulator(
      const nlohmann::json& config = small_models::config("gns")) const {
    auto model = gnn::make_model(config, "test");
    return std::make_unique<gnn::LearnedSimulator>(
        model,
        gnn::Normalisation::from_metadata(metadata, model->noise_std(),
                                          gnn::oil_fraction_change_rms({trajectory})),
        metadata.bounds, metadata.particle_radius);
  }
  gnn::FrameNodes frame(int64_t f) const {
    auto ids = gnn::active_ids(trajectory, f);
    return {gnn::position_history(trajectory, f, ids, metadata.frame_dt),
            trajectory.oil_fraction[f].index_select(0, ids), trajectory.material,
            trajectory.boundary};
  }
};

train::TrainerOptions options(const Tiny& data, const fs::path& out, int steps,
                              std::vector<std::string> extra = {},
                              const std::string& config = kSmoke) {
  train::TrainerOptions o;
  o.config_file = config;
  o.data_dir = data.dir.string();
  o.out_dir = out.string();
  o.overrides = {"/steps=" + std::to_string(steps)};
  for (auto& e : extra) o.overrides.push_back(e);
  return o;
}

}  // namespace

// Every registered model (the registry enumerated: a new model is covered, or fails for want of
// a small config in tests/gnn/small_models.h): a checkpoint reloads to the same model, config and
// statistics, with identical outputs and the same rollout (batch normalisation's running
// statistics included: one training-mode pass moves them first).
class CheckpointOfEveryModel : public ::testing::TestWithParam<std::string> {};

TEST_P(CheckpointOfEveryModel, ReloadsToIdenticalOutputsAndRollout) {
  Tiny data("roundtrip_" + GetParam());
  auto sim = data.simulator(small_models::config(GetParam()));
  auto frame = data.frame(10);
  sim->model().train();
  sim->predict_normalised(frame);
  sim->model().eval();
  torch::NoGradGuard no_grad;
  const auto before = sim->predict_normalised(frame);
  const std::string file = (data.dir / "model.pt").string();
  gnn::TrainingState state;
  state.step = 7;
  gnn::save_checkpoint(file, *sim, gnn::describe_data(data.metadata), state, nullptr);
  auto loaded = gnn::load_checkpoint(file, GetParam());
  loaded.simulator->model().eval();
  EXPECT_EQ(loaded.state.step, 7);
  EXPECT_EQ(loaded.simulator->model().name(), GetParam());
  EXPECT_EQ(loaded.simulator->model().config(), sim->model().config());
  EXPECT_TRUE(
      torch::equal(sim->normalisation().acc_std, loaded.simulator->normalisation().acc_std));
  const auto after = loaded.simulator->predict_normalised(frame);
  EXPECT_TRUE(torch::equal(before, after)) << (before - after).abs().max().item<float>();
  const int64_t frames = 6;
  const auto a = gnn::rollout(*sim, data.trajectory, 5, frames, data.metadata.frame_dt);
  const auto b =
      gnn::rollout(*loaded.simulator, data.trajectory, 5, frames, data.metadata.frame_dt);
  EXPECT_TRUE(torch::equal(a.position, b.position));
}

INSTANTIATE_TEST_SUITE_P(Registered, CheckpointOfEveryModel,
                         ::testing::ValuesIn(gnn::model_names()),
                         [](const auto& info) { return info.param; });

TEST(Checkpoint, ACheckpointOfAnotherModelOrNoneAtAllIsAClearError) {
  Tiny data("badckpt");
  auto sim = data.simulator();
  const std::string file = (data.dir / "model.pt").string();
  gnn::save_checkpoint(file, *sim, gnn::describe_data(data.metadata), {}, nullptr);
  try {
    gnn::load_checkpoint(file, std::string("pagatnet"));
    FAIL() << "no error";
  } catch (const gnn::CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("gns"), std::string::npos) << e.what();
  }
  const std::string junk = (data.dir / "junk.pt").string();
  std::ofstream(junk) << "not a checkpoint";
  EXPECT_THROW(gnn::load_checkpoint(junk), gnn::CheckpointError);
  EXPECT_THROW(gnn::load_checkpoint((data.dir / "none.pt").string()), gnn::CheckpointError);
  // Data of another particle size does not fit the checkpoint.
  auto other = data.metadata;
  other.particle_radius = 0.05;
  EXPECT_THROW(gnn::check_data_fits(gnn::describe_data(data.metadata), other, file),
               gnn::CheckpointError);
}

// Copies every entry of checkpoint `from` to `to`, each through `change(key, tensor)`.
void copy_checkpoint(
    const std::string& from, const std::string& to,
    const std::function<torch::Tensor(const std::string&, torch::Tensor)>& change) {
  torch::serialize::InputArchive in;
  in.load_from(from);
  torch::serialize::OutputArchive copy;
  for (const auto& key : in.keys()) {
    torch::Tensor t;
    ASSERT_TRUE(in.try_read(key, t)) << key;
    copy.write(key, change(key, t));
  }
  copy.save_to(to);
}

// A text entry of another type (the data fuzzer retyped "format" and "model_config") failed inside
// LibTorch with "expected scalar type Byte but found Double", naming no file; exit 1.
TEST(Checkpoint, AnEntryOfAnotherTypeIsAnErrorNamingTheFile) {
  Tiny data("retyped");
  auto sim = data.simulator();
  const std::string file = (data.dir / "model.pt").string();
  gnn::save_checkpoint(file, *sim, gnn::describe_data(data.metadata), {}, nullptr);
  for (const char* entry : {"format", "model_config"}) {
    const std::string bad = (data.dir / "retyped.pt").string();
    copy_checkpoint(file, bad, [&](const std::string& key, torch::Tensor t) {
      return key == entry ? t.to(torch::kFloat64) : t;
    });
    try {
      gnn::load_checkpoint(bad);
      ADD_FAILURE() << entry << ": accepted";
    } catch (const gnn::CheckpointError& e) {
      EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(entry), std::string::npos) << e.what();
    }
  }
}

// A weight changed inside a well-formed file (one set to 1e6 once loaded silently and scored 8 x
// worse) fails the stored checksum; the untouched copy, rewritten the same way, loads.
TEST(Checkpoint, AWeightAlteredInsideTheFileIsRefused) {
  Tiny data("tampered");
  auto sim = data.simulator();
  const std::string file = (data.dir / "model.pt").string();
  gnn::save_checkpoint(file, *sim, gnn::describe_data(data.metadata), {}, nullptr);
  // Copies every entry of the archive, setting the first weight of `altered` (if any) to 1e6.
  auto rewrite = [&](const std::string& out, const std::string& altered) {
    copy_checkpoint(file, out, [&](const std::string& key, torch::Tensor t) {
      if (key != altered) return t;
      t = t.clone();
      t.view(-1)[0] = 1e6;
      return t;
    });
  };
  const std::string first_weight = "param:" + [&] {
    std::string name = sim->model().named_parameters().begin()->key();
    for (auto& c : name)
      if (c == '.') c = '/';
    return name;
  }();
  const std::string same = (data.dir / "same.pt").string(), bad = (data.dir / "bad.pt").string();
  rewrite(same, "");
  rewrite(bad, first_weight);
  EXPECT_NO_THROW(gnn::load_checkpoint(same));
  try {
    gnn::load_checkpoint(bad);
    FAIL() << "an altered weight loaded";
  } catch (const gnn::CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find("checksum"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
  }
}

TEST(Rollout, ReplaysTheRecordedEmissionSchedule) {
  Tiny data("rollout");
  auto sim = data.simulator();
  const int64_t from = 5, frames = tiny::kFrames - 1 - from;
  auto r = gnn::rollout(*sim, data.trajectory, from, frames, data.metadata.frame_dt);
  ASSERT_EQ(r.position.size(0), frames + 1);
  for (int64_t k = 0; k <= frames; ++k)
    EXPECT_TRUE(torch::equal(r.active[k], data.trajectory.active[from + k])) << "frame " << k;
  // Emitted particles enter exactly where and when the recording has them.
  const int64_t k = tiny::kEmitFrame - from;
  auto emitted = torch::arange(tiny::kParticles - tiny::kEmitted, tiny::kParticles);
  EXPECT_TRUE(torch::equal(r.position[k].index_select(0, emitted),
                           data.trajectory.position[tiny::kEmitFrame].index_select(0, emitted)));
  // ... and afterwards move by the model, not by the recording.
  EXPECT_FALSE(
      torch::equal(r.position[k + 2].index_select(0, emitted),
                   data.trajectory.position[tiny::kEmitFrame + 2].index_select(0, emitted)));
  EXPECT_EQ(r.frame_seconds.size(), size_t(frames));
}

TEST(Training, OverfitsATinyDatasetLossFallsTenfold) {
  Tiny data("overfit");
  const fs::path out = data.dir / "run";
  train::Trainer trainer(options(data, out, 300, {"/model/noise_std=0"}));
  trainer.run();
  auto rows = training_log::rows_without_timing(out / "log.csv");
  ASSERT_GE(rows.size(), 3u);
  EXPECT_NE(rows[0].find("loss"), std::string::npos);
  const double first = std::stod(rows[1].substr(rows[1].find(',') + 1));
  const double last = std::stod(rows.back().substr(rows.back().find(',') + 1));
  EXPECT_LT(last, first / 10) << "first logged loss " << first << ", last " << last;
  EXPECT_TRUE(fs::exists(out / "last.pt"));
  EXPECT_TRUE(fs::exists(out / "loss.svg"));
}

TEST(Training, ResumeEqualsAnUninterruptedRun) {
  Tiny data("resume");
  const std::vector<std::string> short_schedule = {"/validate_every=20", "/checkpoint_every=20",
                                                   "/log_every=5"};
  const fs::path straight = data.dir / "straight", split = data.dir / "split";
  train::Trainer(options(data, straight, 40, short_schedule)).run();
  train::Trainer(options(data, split, 20, short_schedule)).run();
  auto resumed = options(data, split, 40, short_schedule);
  resumed.resume = true;
  train::Trainer(resumed).run();
  auto a = training_log::rows_without_timing(straight / "log.csv");
  auto b = training_log::rows_without_timing(split / "log.csv");
  ASSERT_EQ(a.size(), 9u);  // header + 8 rows
  EXPECT_EQ(a, b);
  // A second fresh run into the same folder is refused rather than overwriting it.
  EXPECT_THROW(train::Trainer(options(data, straight, 40, short_schedule)), std::runtime_error);
  // Resuming with another setting than /steps is refused, naming every key that differs.
  auto changed = options(data, split, 60,
                         {"/validate_every=20", "/checkpoint_every=20", "/log_every=5",
                          "/lr_max=0.5", "/model/latent=8"});
  changed.resume = true;
  try {
    train::Trainer trainer(changed);
    ADD_FAILURE() << "expected a ConfigError";
  } catch (const common::ConfigError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("/lr_max"), std::string::npos) << m;
    EXPECT_NE(m.find("/model/latent"), std::string::npos) << m;
    EXPECT_NE(m.find("only /steps may change"), std::string::npos) << m;
  }
  EXPECT_EQ(training_log::rows_without_timing(split / "log.csv"), b) << "the run is untouched";
}

// With a pushforward schedule whose longer unrolls open mid-run, a run interrupted before they
// open resumes as the uninterrupted run (the draws come from the checkpointed sampler), and the
// schedule does change what is trained (its log is not the plain run's).
TEST(Training, APushforwardScheduleResumesAsTheUninterruptedRun) {
  Tiny data("resume_pushforward");
  const std::vector<std::string> schedule = {
      "/validate_every=20", "/checkpoint_every=20", "/log_every=5",
      R"(/pushforward_schedule=[{"from_step":0,"unrolls":0,"weight":1},)"
      R"({"from_step":15,"unrolls":2,"weight":1},{"from_step":25,"unrolls":3,"weight":1}])"};
  const fs::path straight = data.dir / "straight", split = data.dir / "split",
                 plain = data.dir / "plain";
  train::Trainer(options(data, straight, 40, schedule)).run();
  train::Trainer(options(data, split, 20, schedule)).run();
  auto resumed = options(data, split, 40, schedule);
  resumed.resume = true;
  train::Trainer(resumed).run();
  train::Trainer(options(data, plain, 40, {schedule.begin(), schedule.end() - 1})).run();
  const auto a = training_log::rows_without_timing(straight / "log.csv");
  ASSERT_EQ(a.size(), 9u);  // header + 8 rows
  EXPECT_EQ(a, training_log::rows_without_timing(split / "log.csv"));
  EXPECT_NE(a, training_log::rows_without_timing(plain / "log.csv"));
}

// A loss over two frames is the mean of the first frame's loss and the loss of the frame whose
// input is the model's own forecast (as a rollout makes it), and its gradient runs through that
// forecast: it is not the gradient of the same two losses with the forecast taken as data.
TEST(Training, ALossOverTwoFramesFeedsTheModelsForecastWithItsGradient) {
  Tiny data("loss_frames");
  train::Trainer trainer(
      options(data, data.dir / "run", 10, {"/loss_frames=2", "/model/noise_std=0"}));
  auto windows = trainer.sample_windows();
  ASSERT_FALSE(windows.empty());
  const train::TrainingBatch first = trainer.batch_of(windows, 0);
  auto& model = trainer.simulator().model();
  auto gradient_of = [&](torch::Tensor loss) {
    for (auto& p : model.parameters()) p.mutable_grad() = torch::Tensor();
    loss.backward();
    std::vector<torch::Tensor> g;
    for (auto& p : model.parameters()) g.push_back(p.grad().clone());
    return g;
  };
  const torch::Tensor unrolled = trainer.unrolled_loss(windows, first);
  const auto through = gradient_of(unrolled);
  // The same two frames by hand: the second input is the forecast as data (no gradient).
  auto forecast = windows;
  for (auto& w : forecast) {
    const gnn::Trajectory& t = *w.trajectory;
    const auto next =
        trainer.simulator().next_state({w.history, w.fraction, t.material, t.boundary});
    w.history = torch::cat({w.history.slice(1, 1), next.position.unsqueeze(1)}, 1);
    w.fraction = t.oil_fraction[w.frame + 1].index_select(0, w.ids);
  }
  const torch::Tensor by_hand =
      (trainer.loss(first) + trainer.loss(trainer.batch_of(forecast, 1))) / 2;
  EXPECT_NEAR(unrolled.item<double>(), by_hand.item<double>(), 1e-5 * by_hand.item<double>());
  const auto as_data = gradient_of(by_hand);
  double difference = 0, size = 0;
  for (size_t k = 0; k < through.size(); ++k) {
    difference += (through[k] - as_data[k]).pow(2).sum().item<double>();
    size += through[k].pow(2).sum().item<double>();
  }
  EXPECT_GT(std::sqrt(difference), 1e-3 * std::sqrt(size))
      << "the gradient does not run through the forecast";
}

// Trained with a loss over three frames, the model still learns the tiny dataset.
TEST(Training, ALossOverThreeFramesFallsTenfold) {
  Tiny data("loss_frames_train");
  const fs::path out = data.dir / "run";
  train::Trainer(options(data, out, 300, {"/model/noise_std=0", "/loss_frames=3"})).run();
  const auto rows = training_log::rows_without_timing(out / "log.csv");
  ASSERT_GE(rows.size(), 3u);
  const double first = std::stod(rows[1].substr(rows[1].find(',') + 1));
  const double last = std::stod(rows.back().substr(rows.back().find(',') + 1));
  EXPECT_LT(last, first / 10) << "first logged loss " << first << ", last " << last;
}

// A run made before the objectives had sections stores their keys flat in its checkpoint (as the
// committed docs/results checkpoints do): it resumes with today's config, its objective keys
// given in their section or flat, and continues as the uninterrupted run; another value of one
// is refused under its section's pointer.
TEST(Training, ARunStoredWithFlatObjectiveKeysResumesAsTheUninterruptedRun) {
  Tiny data("resume_flat");
  const std::vector<std::string> schedule = {"/validate_every=10", "/checkpoint_every=10",
                                             "/log_every=5"};
  auto with = [&](const std::string& setting) {
    auto overrides = schedule;
    overrides.push_back(setting);
    return overrides;
  };
  const fs::path straight = data.dir / "straight", split = data.dir / "split";
  train::Trainer(options(data, straight, 20, with("/pagat/attention_loss_weight=0.3"), kPagatSmoke))
      .run();
  train::Trainer(options(data, split, 10, with("/pagat/attention_loss_weight=0.3"), kPagatSmoke))
      .run();
  // The checkpoint as a run made before the sections wrote it: the keys of the two objectives
  // of that time at the top level.
  const std::string last = (split / "last.pt").string();
  {
    auto loaded = gnn::load_checkpoint(last);
    nlohmann::json& config = loaded.state.training_config;
    for (const char* section : {"acceleration_mse", "pagat"}) {
      const nlohmann::json keys = config.at(section);
      config.erase(section);
      for (auto it = keys.begin(); it != keys.end(); ++it) config[it.key()] = *it;
    }
    ASSERT_EQ(config.at("attention_loss_weight"), 0.3);
    torch::optim::Adam adam(loaded.simulator->model().parameters());
    gnn::load_optimizer_state(last, adam);
    gnn::save_checkpoint(last, *loaded.simulator, loaded.data, loaded.state, &adam);
  }
  auto changed = options(data, split, 20, with("/pagat/attention_loss_weight=0.5"), kPagatSmoke);
  changed.resume = true;
  try {
    train::Trainer trainer(changed);
    ADD_FAILURE() << "expected a ConfigError";
  } catch (const common::ConfigError& e) {
    EXPECT_EQ(e.pointer(), "/pagat/attention_loss_weight") << e.what();
  }
  auto resumed = options(data, split, 20, with("/attention_loss_weight=0.3"), kPagatSmoke);
  resumed.resume = true;
  train::Trainer(resumed).run();
  const auto rows = training_log::rows_without_timing(straight / "log.csv");
  ASSERT_EQ(rows.size(), 5u);  // header + 4 rows
  EXPECT_EQ(training_log::rows_without_timing(split / "log.csv"), rows);
}

TEST(SegmentOps, MatchPlainGatherAndScatterInValueAndGradient) {
  torch::manual_seed(11);
  auto points = torch::rand({300, 3});
  auto graph = gnn::build_radius_graph(points, torch::zeros({0, 3}), 0.2);
  const int64_t n = 300;
  auto order = gnn::edge_order(graph.edge_index, n);
  ASSERT_TRUE(order.canonical);
  const int64_t E = graph.edge_index.size(1);
  auto nodes = torch::randn({n, 8}, torch::requires_grad());
  auto edges = torch::randn({E, 8}, torch::requires_grad());
  auto weight_e = torch::randn({E, 8}), weight_n = torch::randn({n, 8});
  auto fast = (gnn::gather_receivers(nodes, order) * weight_e).sum() +
              (gnn::gather_senders(nodes * 2, order) * weight_e).sum() +
              (gnn::sum_to_receivers(edges, order, n) * weight_n).sum();
  auto fast_nodes = torch::autograd::grad({fast}, {nodes, edges});
  auto plain = (nodes.index_select(0, graph.edge_index[1]) * weight_e).sum() +
               ((nodes * 2).index_select(0, graph.edge_index[0]) * weight_e).sum() +
               (torch::zeros({n, 8}).index_add(0, graph.edge_index[1], edges) * weight_n).sum();
  auto grads = torch::autograd::grad({plain}, {nodes, edges});
  EXPECT_NEAR(fast.item<double>(), plain.item<double>(), 1e-3);
  EXPECT_TRUE(torch::allclose(fast_nodes[0], grads[0], 1e-4, 1e-4));
  EXPECT_TRUE(torch::allclose(fast_nodes[1], grads[1], 1e-4, 1e-4));
  // An unsorted edge list is not canonical and takes the plain path.
  EXPECT_FALSE(gnn::edge_order(graph.edge_index.flip(1), n).canonical);
}

TEST(GnsModel, InferenceInChunksEqualsTheAutogradPath) {
  torch::manual_seed(12);
  auto points = torch::rand({400, 3});
  auto graph = gnn::build_radius_graph(points, torch::zeros({0, 3}), 0.25);
  ASSERT_GT(graph.edge_index.size(1), 3000);  // several chunks of 1024 edges
  gnn::GraphInput g;
  g.node_features = torch::randn({400, gnn::kNodeFeatures});
  g.node_type = torch::randint(0, 2, {400}, torch::kInt64);
  g.edge_index = graph.edge_index;
  g.edge_features = torch::randn({graph.edge_index.size(1), gnn::kEdgeFeatures});
  g.fluid = torch::ones({400}, torch::kBool);
  auto model = gnn::make_model({{"model", "gns"}, {"latent", 32}, {"layers", 3}}, "test");
  auto with_grad = model->acceleration(g);
  torch::NoGradGuard no_grad;
  auto chunked = model->acceleration(g);
  EXPECT_TRUE(torch::allclose(with_grad, chunked, 1e-4, 1e-5))
      << (with_grad - chunked).abs().max().item<float>();
}

// DPI-Nets' fused inference (dpi_inference.cpp) against its autograd path on the same weights
// and graph (400 nodes, several chunks of 1,024 edges, 3 propagation steps, encoders of 2 hidden
// layers), chunks side by side on 2 threads with BLAS on 1 and in turn with BLAS on 2: float32
// sums in another order, so the outputs agree to 1e-4 relative, 1e-5 absolute.
TEST(DpiModel, InferenceInChunksEqualsTheAutogradPath) {
  const int blas_before = gnn::blas_threads(), threads_before = torch::get_num_threads();
  torch::manual_seed(13);
  auto points = torch::rand({400, 3});
  auto graph = gnn::build_radius_graph(points, torch::zeros({0, 3}), 0.25);
  ASSERT_GT(graph.edge_index.size(1), 3000);
  gnn::GraphInput g;
  g.node_features = torch::randn({400, gnn::kNodeFeatures});
  g.node_type = torch::randint(0, 3, {400}, torch::kInt64);
  g.edge_index = graph.edge_index;
  g.edge_features = torch::randn({graph.edge_index.size(1), gnn::kEdgeFeatures});
  g.fluid = torch::ones({400}, torch::kBool);
  auto model = gnn::make_model({{"model", "dpi"},
                                {"particle_width", 24},
                                {"relation_width", 40},
                                {"effect_width", 32},
                                {"propagation_steps", 3}},
                               "test");
  auto& dpi = dynamic_cast<gnn::DpiModel&>(*model);
  auto with_grad = dpi.next_velocity(g);
  ASSERT_TRUE(with_grad.requires_grad());  // the plain path, with autograd
  for (const gnn::RuntimeSettings mix : {gnn::RuntimeSettings{2, 1}, gnn::RuntimeSettings{1, 2}}) {
    gnn::configure_runtime(mix);
    torch::NoGradGuard no_grad;
    auto chunked = dpi.next_velocity(g);
    EXPECT_TRUE(torch::allclose(with_grad, chunked, 1e-4, 1e-5))
        << mix.threads << " + " << mix.blas_threads << ": "
        << (with_grad - chunked).abs().max().item<float>();
  }
  gnn::configure_runtime({threads_before, blas_before});
}

// The processor's hand-written backward (gns_processor_step.h) against LibTorch's autograd on
// the same weights and graph (400 nodes, ~3,000 edges: three chunks of 1,024; 3 steps; MLPs of
// 2 and of 3 hidden layers), with the chunks side by side on 2 threads (BLAS on 1) and one after
// another (BLAS on 2): every parameter's gradient and the input features' gradient agree to a
// relative error (|a - b| / |b|, Frobenius norms) below 1e-4 (float32 sums in another order;
// measured up to 5e-6), and so do the outputs.
TEST(GnsModel, LeanBackwardEqualsAutograd) {
  const int blas_before = gnn::blas_threads(), threads_before = torch::get_num_threads();
  for (const auto& [threads, blas, hidden] :
       {std::tuple{2, 1, 2}, std::tuple{1, 2, 2}, std::tuple{2, 1, 3}}) {
    SCOPED_TRACE("threads " + std::to_string(threads) + ", BLAS threads " + std::to_string(blas) +
                 ", mlp_hidden_layers " + std::to_string(hidden));
    gnn::configure_runtime({threads, blas});
    torch::manual_seed(13);
    auto points = torch::rand({400, 3});
    auto graph = gnn::build_radius_graph(points, torch::zeros({0, 3}), 0.25);
    gnn::GraphInput g;
    g.node_features = torch::randn({400, gnn::kNodeFeatures}, torch::requires_grad());
    g.node_type = torch::randint(0, 2, {400}, torch::kInt64);
    g.edge_index = graph.edge_index;
    g.edge_features = torch::randn({graph.edge_index.size(1), gnn::kEdgeFeatures});
    g.fluid = torch::ones({400}, torch::kBool);
    auto model = std::dynamic_pointer_cast<gnn::GnsModel>(gnn::make_model(
        {{"model", "gns"}, {"latent", 32}, {"layers", 3}, {"mlp_hidden_layers", hidden}}, "test"));
    ASSERT_TRUE(model);
    const auto weight = torch::randn({400, 3});
    auto gradients = [&](bool lean, torch::Tensor* out) {
      model->use_lean_backward(lean);
      model->zero_grad();
      g.node_features.mutable_grad() = torch::Tensor();
      *out = model->acceleration(g);
      (*out * weight).sum().backward();
      std::vector<torch::Tensor> grads;
      for (const auto& p : model->named_parameters()) {
        EXPECT_TRUE(p.value().grad().defined()) << p.key() << " has no gradient";
        grads.push_back(p.value().grad().defined() ? p.value().grad().clone()
                                                   : torch::zeros_like(p.value()));
      }
      grads.push_back(g.node_features.grad().clone());
      return grads;
    };
    torch::Tensor out_lean, out_autograd;
    const auto lean = gradients(true, &out_lean);
    const auto reference = gradients(false, &out_autograd);
    EXPECT_TRUE(torch::allclose(out_lean, out_autograd, 1e-4, 1e-5));
    double worst = 0;
    for (size_t k = 0; k < lean.size(); ++k) {
      const double rel =
          (lean[k] - reference[k]).norm().item<double>() / reference[k].norm().item<double>();
      worst = std::max(worst, rel);
      EXPECT_LT(rel, 1e-4) << "gradient " << k << " of " << lean.size();
    }
    std::cout << "largest relative gradient error " << worst << "\n";
  }
  gnn::configure_runtime({threads_before, blas_before});
}

// Training on freshly simulated data without a file: the recorder's tensors go straight into
// the same windows, loss and rollout as a dataset read from HDF5.
TEST(InProcess, RecorderTensorsTrainAndRollOutWithoutAFile) {
  const sph::LoadedScene s = sph::parse_scene(nlohmann::json::parse(R"({
    "name": "record", "particle_radius": 0.02, "end_time": 0.2, "output": {"frame_dt": 0.02},
    "boxes": [{"min": [0, 0, 0], "max": [0.4, 0.4, 0.6]}],
    "fluid_blocks": [{"min": [0, 0, 0], "max": [0.2, 0.2, 0.2]}],
    "emitters": [{"centre": [0.3, 0.3, 0.4], "radius": 0.03, "rate": 0.0005, "speed": 1,
                  "stop": 0.1, "material": "oil"}]})"),
                                              "record.json");
  sph::Simulation sim(s.config);
  sph::TensorRecorder recorder(sim, 1);
  recorder.record(sim);
  for (int frame = 1; frame <= 10; ++frame) {
    sim.advance_to(0.02 * frame, frame);
    recorder.record(sim);
  }
  auto t =
      gnn::from_recorded(recorder.take(), nlohmann::json::parse(
                                              R"({"water": {"density": 1000, "viscosity": 0.001},
                                                       "oil": {"density": 940, "viscosity": 0.004}})"));
  ASSERT_EQ(t.frames(), 11);
  EXPECT_GT((t.particle_type == gnn::kOil).sum().item<int64_t>(), 0);
  EXPECT_FALSE(torch::equal(t.active[0], t.active[10]));  // the emitter added particles
  gnn::DatasetMetadata m;
  m.frame_dt = 0.02;
  m.bounds = {{{0, 0.4}, {0, 0.4}, {0, 0.6}}};
  m.vel_mean = torch::zeros({3});
  m.acc_mean = torch::zeros({3});
  m.vel_std = torch::full({3}, 0.01f);
  m.acc_std = torch::full({3}, 0.001f);
  auto model =
      gnn::make_model({{"model", "gns"}, {"latent", 16}, {"layers", 2}, {"radius", 0.08}}, "test");
  gnn::LearnedSimulator simulator(model, gnn::Normalisation::from_metadata(m, 0, 0.01), m.bounds);
  auto ids = gnn::active_ids(t, 6);
  gnn::FrameNodes nodes{gnn::position_history(t, 6, ids, m.frame_dt),
                        t.oil_fraction[6].index_select(0, ids), t.material, t.boundary};
  auto loss = simulator.predict_normalised(nodes).pow(2).mean();
  loss.backward();
  EXPECT_TRUE(model->parameters()[0].grad().defined());
  auto r = gnn::rollout(simulator, t, 5, 5, m.frame_dt);
  EXPECT_TRUE(torch::equal(r.active[5], t.active[10]));
}

// The training loss of the first and of the last log.csv row.
std::pair<double, double> first_and_last_loss(const fs::path& log) {
  auto rows = training_log::rows_without_timing(log);
  EXPECT_GE(rows.size(), 3u);
  if (rows.size() < 3) return {0, 0};
  auto loss = [](const std::string& row) { return std::stod(row.substr(row.find(',') + 1)); };
  return {loss(rows[1]), loss(rows.back())};
}

// The acceleration DPI-Nets reports is the one that takes each fluid particle's last velocity to
// the velocity its decoder predicts: one Euler step moves a particle by exactly that velocity.
TEST(DpiModel, TheAccelerationTakesTheLastVelocityToThePredictedOne) {
  Tiny data("dpi_velocity");
  auto sim = data.simulator(kSmallDpi);
  auto frame = data.frame(10);
  torch::NoGradGuard no_grad;
  auto& model = dynamic_cast<gnn::DpiModel&>(sim->model());
  const int64_t n = frame.history.size(0);
  const auto u = model.next_velocity(sim->encode(frame)).slice(0, 0, n);
  const auto& s = sim->normalisation();
  const auto predicted_velocity = u * s.vel_std + s.vel_mean;  // m per frame
  const auto last = frame.history.select(1, gnn::kWindow - 1);
  const auto moved = sim->next_position(frame) - last;
  EXPECT_TRUE(torch::allclose(moved, predicted_velocity, 0, 1e-6))
      << (moved - predicted_velocity).abs().max().item<float>();
}

// The same fixture and schedule as the GNS test: the loss falls tenfold in 300 steps.
TEST(DpiModel, TrainingOnTheTinyDatasetLossFallsTenfold) {
  Tiny data("dpi_overfit");
  const fs::path out = data.dir / "run";
  train::Trainer trainer(options(data, out, 300, {"/model/noise_std=0"}, kDpiSmoke));
  trainer.run();
  EXPECT_EQ(trainer.simulator().model().name(), "dpi");
  const auto [first, last] = first_and_last_loss(out / "log.csv");
  std::cout << "[ measured ] dpi loss: first logged " << first << ", last " << last << "\n";
  EXPECT_LT(last, first / 10) << "first logged loss " << first << ", last " << last;
  EXPECT_TRUE(fs::exists(out / "last.pt"));
  EXPECT_NO_THROW(gnn::load_checkpoint((out / "last.pt").string(), std::string("dpi")));
}

// PAGATNet through the simulator: the typing is built from the frame (the data's particle
// radius reaches it), a checkpoint reloads to identical outputs in eval mode (batch
// normalisation's running statistics included), and the loss falls tenfold in 300 steps on the
// tiny dataset, like GNS's and DPI-Nets'.
TEST(PagatModel, CheckpointRoundTripGivesIdenticalOutputs) {
  Tiny data("pagat_roundtrip");
  auto sim = data.simulator(kSmallPagat);
  auto frame = data.frame(10);
  const auto g = sim->encode(frame);
  ASSERT_TRUE(g.node_class.defined());
  EXPECT_GT((g.node_class == gnn::kWaterInner).sum().item<int64_t>(), 0);
  EXPECT_GT((g.node_class == gnn::kWaterSurface).sum().item<int64_t>(), 0);
  sim->model().train();
  sim->predict_normalised(frame);  // one training-mode pass moves the running statistics
  sim->model().eval();
  torch::NoGradGuard no_grad;
  auto before = sim->predict_normalised(frame);
  const std::string file = (data.dir / "model.pt").string();
  gnn::save_checkpoint(file, *sim, gnn::describe_data(data.metadata), {}, nullptr);
  auto loaded = gnn::load_checkpoint(file, std::string("pagat"));
  loaded.simulator->model().eval();
  EXPECT_EQ(loaded.simulator->particle_radius(), data.metadata.particle_radius);
  auto after = loaded.simulator->predict_normalised(frame);
  EXPECT_TRUE(torch::equal(before, after)) << (before - after).abs().max().item<float>();
}

TEST(PagatModel, TrainingOnTheTinyDatasetLossFallsTenfold) {
  Tiny data("pagat_overfit");
  const fs::path out = data.dir / "run";
  train::Trainer trainer(options(data, out, 300, {"/model/noise_std=0"}, kPagatSmoke));
  trainer.run();
  EXPECT_EQ(trainer.simulator().model().name(), "pagat");
  const auto [first, last] = first_and_last_loss(out / "log.csv");
  std::cout << "[ measured ] pagat loss: first logged " << first << ", last " << last << "\n";
  EXPECT_LT(last, first / 10) << "first logged loss " << first << ", last " << last;
  EXPECT_NO_THROW(gnn::load_checkpoint((out / "last.pt").string(), std::string("pagat")));
}

// spill-train's teacher-student path: a teacher trained on the tiny dataset, then a student
// distilled from it (--teacher): the student gets one adapter per block from the teacher's width
// and its run records the teacher; resuming it without --teacher, or giving a teacher to a GNS
// config, is a clear error.
TEST(PagatModel, AStudentTrainsAgainstAFrozenTeacher) {
  Tiny data("pagat_student");
  const fs::path teacher_run = data.dir / "teacher", student_run = data.dir / "student";
  train::Trainer(options(data, teacher_run, 20, {}, kPagatSmoke)).run();
  const std::string teacher = (teacher_run / "last.pt").string();
  const auto teacher_before = gnn::load_checkpoint(teacher);
  auto o = options(data, student_run, 20, {"/model/latent=8", "/model/blocks=1"}, kPagatSmoke);
  o.teacher = teacher;
  train::Trainer student(o);
  student.run();
  const auto loaded = gnn::load_checkpoint((student_run / "last.pt").string(), "pagat");
  EXPECT_EQ(loaded.simulator->model().config().at("teacher_latent"), 16);
  const auto run_config = nlohmann::json::parse(std::ifstream(student_run / "config.json"));
  EXPECT_EQ(run_config.at("teacher"), teacher);
  // The teacher's file is untouched (it was only read).
  const auto teacher_after = gnn::load_checkpoint(teacher);
  auto before = teacher_before.simulator->model().parameters();
  auto after = teacher_after.simulator->model().parameters();
  for (size_t k = 0; k < before.size(); ++k) EXPECT_TRUE(torch::equal(before[k], after[k]));

  auto resume = options(data, student_run, 30, {"/model/latent=8", "/model/blocks=1"}, kPagatSmoke);
  resume.resume = true;
  auto refused = [&](train::TrainerOptions o, const std::vector<std::string>& words) {
    try {
      train::Trainer(o).run();
      ADD_FAILURE() << "resumed with teacher \"" << o.teacher << "\"";
    } catch (const common::InputError& e) {  // bad input: exit 2
      for (const auto& w : words)
        EXPECT_NE(std::string(e.what()).find(w), std::string::npos) << w << ": " << e.what();
    }
  };
  refused(resume, {"--teacher", teacher});
  // Another teacher (the same model, other weights) is refused, naming both; the run is as it was.
  const fs::path other_run = data.dir / "other_teacher";
  train::Trainer(options(data, other_run, 2, {}, kPagatSmoke)).run();
  auto with_other = resume;
  with_other.teacher = (other_run / "last.pt").string();
  refused(with_other, {"not the teacher", teacher, with_other.teacher,
                       run_config.at("teacher_checksum").get<std::string>()});
  EXPECT_EQ(gnn::load_checkpoint((student_run / "last.pt").string()).state.step, 20);
  // A teacher given to a run trained without one is refused too.
  auto teacher_resumed = options(data, teacher_run, 30, {}, kPagatSmoke);
  teacher_resumed.resume = true;
  teacher_resumed.teacher = teacher;
  refused(teacher_resumed, {"--teacher", "without a teacher"});
  // The same teacher at another path is the same teacher: the student resumes.
  const fs::path copy = data.dir / "teacher_copy.pt";
  fs::copy_file(teacher, copy);
  auto with_copy = resume;
  with_copy.teacher = copy.string();
  train::Trainer(with_copy).run();
  EXPECT_EQ(gnn::load_checkpoint((student_run / "last.pt").string()).state.step, 30);
  auto gns = options(data, data.dir / "gns_student", 5);
  gns.teacher = teacher;
  try {
    train::Trainer(gns).run();
    ADD_FAILURE() << "a GNS config took a teacher";
  } catch (const common::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("--teacher"), std::string::npos) << e.what();
  }
}

// A model that diverges (here a weight made NaN) stops the rollout with an error naming the
// trajectory and the frame; it surfaced as "radius graph: a fluid position is not finite",
// naming neither.
TEST(Rollout, ADivergingModelIsNamedWithTheTrajectoryAndFrame) {
  Tiny data("diverging_rollout");
  auto sim = data.simulator();
  {
    torch::NoGradGuard no_grad;
    sim->model().parameters().back().fill_(std::nan(""));
  }
  try {
    gnn::rollout(*sim, data.trajectory, 5, 4, data.metadata.frame_dt);
    ADD_FAILURE() << "a rollout of NaN positions went on";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(data.trajectory.source), std::string::npos) << m;
    EXPECT_NE(m.find("diverged at rollout frame 1"), std::string::npos) << m;
  }
}

// Zero physical acceleration (not a normalised zero: the tiny dataset's mean acceleration is
// gravity and drag), so a rollout moves every fluid particle by its last displacement, frame
// after frame; emitted particles enter on the recorded schedule and then keep their velocity.
TEST(ConstantVelocity, RolloutKeepsEveryFluidVelocity) {
  Tiny data("constant_rollout");
  auto sim = data.simulator(kConstantVelocity);
  EXPECT_TRUE(sim->model().parameters().empty());
  auto frame = data.frame(10);
  const auto normalised = sim->predict_normalised(frame);
  EXPECT_GT(normalised.abs().max().item<double>(), 0.1);
  EXPECT_LT(sim->denormalise_acceleration(normalised).abs().max().item<double>(), 1e-9);

  const int64_t from = 5, frames = tiny::kFrames - 1 - from;
  auto r = gnn::rollout(*sim, data.trajectory, from, frames, data.metadata.frame_dt);
  for (int64_t k = 0; k <= frames; ++k)
    EXPECT_TRUE(torch::equal(r.active[k], data.trajectory.active[from + k])) << "frame " << k;
  // The first step continues the recorded velocity.
  const auto& t = data.trajectory.position;
  const auto start = data.trajectory.active[from - 1] & data.trajectory.active[from];
  EXPECT_TRUE(torch::allclose((r.position[1] - r.position[0]).index({start}),
                              (t[from] - t[from - 1]).index({start}), 0, 1e-6));
  int64_t checked = 0;
  for (int64_t k = 1; k < frames; ++k) {
    const auto both = r.active[k - 1] & r.active[k] & r.active[k + 1];
    const auto before = (r.position[k] - r.position[k - 1]).index({both});
    const auto after = (r.position[k + 1] - r.position[k]).index({both});
    EXPECT_TRUE(torch::allclose(after, before, 0, 2e-6))
        << "frame " << k << ": " << (after - before).abs().max().item<float>();
    checked += both.sum().item<int64_t>();
  }
  EXPECT_GT(checked, int64_t(frames - 1) * (tiny::kParticles - tiny::kEmitted));
  // The emitted particles moved by themselves after entering.
  const auto emitted = torch::arange(tiny::kParticles - tiny::kEmitted, tiny::kParticles);
  const int64_t k = tiny::kEmitFrame - from;
  EXPECT_FALSE(torch::equal(r.position[k + 2].index_select(0, emitted),
                            r.position[k].index_select(0, emitted)));
}

// Nothing to train: a clear error before any output exists, not a LibTorch failure mid-run.
TEST(ConstantVelocity, TrainingIsRefusedWithAClearError) {
  Tiny data("constant_train");
  const fs::path out = data.dir / "run";
  try {
    train::Trainer trainer(
        options(data, out, 10, {"/model_config=../models/constant_velocity.json", "/model={}"}));
    ADD_FAILURE() << "expected a ConfigError";
  } catch (const common::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("constant_velocity has no parameters to train"),
              std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("constant_velocity.json"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(out));
}
