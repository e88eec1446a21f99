#include "train/trainer.h"

#include <ATen/CPUGeneratorImpl.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "common/checked_file.h"
#include "common/config_visitors.h"
#include "common/json_file.h"
#include "common/output_folder.h"
#include "common/progress.h"
#include "common/stop_signals.h"
#include "common/svg_plot.h"
#include "gnn/data/frame_window.h"
#include "gnn/eval/rollout.h"
#include "gnn/eval/standalone_skill.h"
#include "gnn/training/noise.h"
#include "train/pushforward.h"

namespace train {
namespace fs = std::filesystem;

namespace {

const char* kLogHeader =
    "step,loss,lr,elapsed_s,steps_per_s,valid_one_step_loss,valid_rollout_mse,"
    "valid_standalone_fss";

std::string checkpoint_path(const std::string& dir) {
  return (fs::path(dir) / "last.pt").string();
}

// best_checkpoint_trajectories: the checkpoint with the best standalone score, and its record.
fs::path best_path(const std::string& dir) {
  return fs::path(dir) / "best.pt";
}
fs::path best_record_path(const std::string& dir) {
  return fs::path(dir) / "best.json";
}

// Keeps the header and the rows up to `step` (rows after the checkpoint are redone on resume).
void truncate_log(const std::string& file, int64_t step) {
  std::ifstream in(file);
  std::vector<std::string> keep;
  std::string line;
  while (std::getline(in, line)) {
    if (keep.empty()) {
      keep.push_back(line);
      continue;
    }
    if (std::stoll(line.substr(0, line.find(','))) <= step) keep.push_back(line);
  }
  in.close();
  std::string text;
  for (const auto& l : keep) text += l + "\n";
  common::write_file_atomically(file, text);
}

}  // namespace

TrainingData read_training_data(const std::string& dir) {
  TrainingData d;
  d.metadata = gnn::read_metadata((fs::path(dir) / "metadata.json").string());
  d.train = gnn::read_split(dir, "train", d.metadata);
  d.valid = gnn::read_split(dir, "valid", d.metadata);
  d.description = dir;
  return d;
}

Trainer::Trainer(TrainerOptions options)
    : Trainer(options, [dir = options.data_dir] { return read_training_data(dir); }) {}

Trainer::Trainer(TrainerOptions options, const std::function<TrainingData()>& load_data)
    : options_(std::move(options)) {
  config_ = load_training_config(options_.config_file, options_.overrides);
  const std::string last = checkpoint_path(options_.out_dir);
  if (options_.resume && !fs::exists(last))
    throw gnn::CheckpointError(last + ": nothing to resume (no checkpoint in the run folder)");
  if (!options_.resume && fs::exists(last))
    throw common::OutputPathError("--out " + options_.out_dir +
                                  ": already holds a training run (last.pt); use --resume to "
                                  "continue it, or another --out");
  common::check_can_create(options_.out_dir, "--out");
  take_data(load_data());
  if (options_.resume)
    resume_model(last);
  else
    start_model();
  // A model without parameters (the constant-velocity floor) has nothing to learn: Adam would get
  // no tensors and the loss no gradient to follow (backward() fails inside LibTorch).
  if (simulator_->model().parameters().empty())
    throw common::ConfigError(config_.model_file, "/model",
                              simulator_->model().name() + " has no parameters to train");
  simulator_->to(options_.device);
  choose_objective();
  optimizer_ = std::make_unique<torch::optim::Adam>(
      simulator_->model().parameters(), torch::optim::AdamOptions(config_.training.lr_max));
  noise_generator_ = at::make_generator<at::CPUGeneratorImpl>(uint64_t(config_.training.seed));
  sampler_.seed(uint64_t(config_.training.seed));
  if (options_.resume) {
    gnn::load_optimizer_state(last, *optimizer_);
    std::istringstream(state_.sampler_state) >> sampler_;
    if (state_.noise_generator_state.defined())
      noise_generator_.set_state(state_.noise_generator_state);
  }
  if (DataParallel* parallel = options_.parallel) {
    if (config_.training.batch_size < parallel->world())
      throw common::ConfigError(
          options_.config_file, "/batch_size",
          std::to_string(config_.training.batch_size) + " windows cannot be shared by " +
              std::to_string(parallel->world()) + " ranks: every rank needs at least one");
    // Seeded alike, the ranks start alike; rank 0's weights make sure of it.
    std::vector<torch::Tensor> state = simulator_->model().parameters();
    for (const auto& b : simulator_->model().buffers()) state.push_back(b);
    parallel->broadcast_from_first(state);
  }
}

// The run's data, checked for the windows training and validation take.
void Trainer::take_data(TrainingData data) {
  metadata_ = std::move(data.metadata);
  train_ = std::move(data.train);
  valid_ = std::move(data.valid);
  data_description_ = std::move(data.description);
  if (train_.empty() || valid_.empty())
    throw gnn::DatasetError(metadata_.file + ": no " +
                            (train_.empty() ? "training" : "validation") +
                            " trajectories (training needs at least one of each)");
  for (const auto& t : train_)
    if (t.frames() < frames_per_window(config_.training))
      throw gnn::DatasetError(t.source + ": too few frames for a training window");
  // Validation takes a window and the frame after it (it once crashed at the first validation
  // with a LibTorch backtrace on shorter trajectories).
  for (const auto& t : valid_)
    if (t.frames() < gnn::kWindow + 1)
      throw gnn::DatasetError(t.source + ": " + std::to_string(t.frames()) +
                              " frames, a validation window needs at least " +
                              std::to_string(gnn::kWindow + 1));
}

// The model, its training state and configs from the run's last checkpoint; the run goes on
// with its own stored configs, only the step count may be raised.
void Trainer::resume_model(const std::string& last) {
  // The best standalone score so far, which best.pt has to be beaten by.
  const fs::path best = best_record_path(options_.out_dir);
  if (fs::exists(best))
    best_skill_ = common::load_json_file(best.string(), "the best checkpoint's record")
                      .at("valid_standalone_fss")
                      .get<double>();
  auto loaded = gnn::load_checkpoint(last, config_.model_json.value("model", ""));
  gnn::check_data_fits(loaded.data, metadata_, last);
  // A run made before the objectives had sections stores their keys flat: read them as today's.
  nlohmann::json stored = loaded.state.training_config;
  gnn::move_flat_objective_keys(stored, last);
  // A config that now says something else is refused, naming every key that differs (a resumed
  // run that silently ignored a new learning rate once passed for a run with it).
  {
    const auto differ = keys_that_differ(stored, config_.training_json);
    if (!differ.empty()) {
      std::string keys;
      for (const auto& k : differ) keys += (keys.empty() ? "" : ", ") + k;
      throw common::ConfigError(options_.config_file, differ.front(),
                                "differs from the run being resumed (" + last + ") at " + keys +
                                    "; only /steps may change on --resume: start a new run "
                                    "with another --out to train with other settings");
    }
  }
  const int steps = config_.training.steps;
  config_.training_json = stored;
  nlohmann::json t = stored;
  t.erase("model");
  common::JsonReader::read_struct(t, last, "/training_config", config_.training);
  config_.training.steps = steps;
  config_.training_json["steps"] = steps;
  simulator_ = std::move(loaded.simulator);
  state_ = loaded.state;
  state_.training_config = config_.training_json;
  // Fewer steps than were trained would do nothing, and once exited 0 without saying so.
  if (steps < state_.step)
    throw common::ConfigError(options_.config_file, "/steps",
                              "asks for " + std::to_string(steps) + " steps, below the " +
                                  std::to_string(state_.step) + " that " + last +
                                  " has trained; raise /steps to go on");
  load_teacher();
  check_resumed_teacher(last);
}

// A resumed student goes on with the teacher it was distilled from (its checkpoint records the
// teacher's path and weights checksum), and a run without a teacher goes on without one: another
// teacher would train it under another objective than its config.json records.
void Trainer::check_resumed_teacher(const std::string& last) {
  const bool has_adapters = simulator_->model().config().value("teacher_latent", 0) > 0;
  if (has_adapters && !teacher_)
    throw common::InputError(last +
                             ": this student was being distilled from a teacher; resume it with "
                             "--teacher (the same checkpoint" +
                             (state_.teacher.is_object()
                                  ? ", " + state_.teacher.value("path", std::string("?"))
                                  : std::string()) +
                             ")");
  if (!has_adapters && teacher_)
    throw common::InputError("--teacher " + options_.teacher + ": the run being resumed (" + last +
                             ") trains without a teacher; resume it without --teacher");
  if (!teacher_ || !state_.teacher.is_object()) return;  // recorded only since the check came
  const std::string first = state_.teacher.value("path", std::string("?"));
  if (state_.teacher.value("checksum", std::string()) != teacher_record_.at("checksum"))
    throw common::InputError("--teacher " + options_.teacher +
                             ": not the teacher this student was distilled from (" + last +
                             " records " + first + ", weights checksum " +
                             state_.teacher.value("checksum", std::string("?")) +
                             "; this one has " + teacher_record_.at("checksum").get<std::string>() +
                             "); resume with that teacher, or start a new run with another --out");
  if (first != teacher_record_.at("path") && options_.log)
    *options_.log << "note: --teacher " << options_.teacher << " holds the same weights as "
                  << first << ", the teacher recorded for this run\n";
}

// A new model from the config, with seeded initial weights.
void Trainer::start_model() {
  // The initial weights come from LibTorch's global generator: seeded, so that a run is
  // reproducible from its config.
  torch::manual_seed(uint64_t(config_.training.seed));
  load_teacher();
  // A student gets an adapter per block from the teacher's latent width.
  if (teacher_) config_.model_json["teacher_latent"] = teacher_->config().value("latent", 0);
  state_.teacher = teacher_record_;
  auto model = gnn::make_model(config_.model_json, config_.model_file);
  simulator_ = std::make_unique<gnn::LearnedSimulator>(
      model,
      gnn::Normalisation::from_metadata(metadata_, model->noise_std(),
                                        gnn::oil_fraction_change_rms(train_)),
      metadata_.bounds, metadata_.particle_radius);
  state_.training_config = config_.training_json;
}

// The objective the model trains with, its teacher (if any) on the run's device.
void Trainer::choose_objective() {
  gnn::ObjectiveInputs objective;
  objective.settings = config_.training.objectives;
  objective.steps = config_.training.steps;
  if (teacher_) teacher_->to(options_.device);
  objective.teacher = teacher_;
  try {
    objective_ = gnn::make_objective(simulator_->model(), objective);
  } catch (const std::invalid_argument& e) {
    // A teacher the student cannot be paired with (width, blocks, graph radius) is bad input.
    if (!teacher_) throw;
    throw common::InputError("--teacher " + options_.teacher + " does not fit the student of " +
                             options_.config_file + ": " + e.what());
  }
}

std::vector<LossWindow> Trainer::sample_windows() {
  const auto& c = config_.training;
  const int64_t push = pushforward_frames(c, state_.step, sampler_);
  const int64_t frames_after = c.loss_frames;  // recorded frames each window's loss reads
  std::vector<LossWindow> windows;
  const int world = options_.parallel ? options_.parallel->world() : 1;
  const int rank = options_.parallel ? options_.parallel->rank() : 0;
  for (int b = 0; b < c.batch_size; ++b) {
    const auto& t = train_[std::uniform_int_distribution<size_t>(0, train_.size() - 1)(sampler_)];
    // Loss frame: a full window of recorded history behind the pushed-forward start, and the
    // loss frames' targets recorded after it.
    const int64_t frame = std::uniform_int_distribution<int64_t>(
        gnn::kWindow - 1 + push, t.frames() - 1 - frames_after)(sampler_);
    auto ids = gnn::active_ids(t, frame - push);
    if (push > 0 || frames_after > 1) {  // only particles present through the whole unroll
      auto present =
          t.active.slice(0, frame - push, frame + frames_after + 1).index_select(1, ids).all(0);
      ids = ids.index({present});
    }
    if (b % world != rank) {
      // Another rank's window: its noise is drawn all the same, so that every rank's streams
      // stay those of one process (and a checkpoint resumes at any world size).
      gnn::random_walk_noise(torch::zeros({ids.size(0), gnn::kWindow, 3}),
                             simulator_->model().noise_std(), noise_generator_);
      continue;
    }
    auto history = gnn::position_history(t, frame - push, ids, metadata_.frame_dt);
    auto fraction = t.oil_fraction[frame - push].index_select(0, ids);
    for (int64_t k = 0; k < push; ++k) {
      const gnn::NextState next =
          simulator_->next_state({history, fraction, t.material, t.boundary});
      history = torch::cat({history.slice(1, 1), next.position.unsqueeze(1)}, 1);
      fraction = next.oil_fraction;
    }
    auto noisy = gnn::random_walk_noise(history, simulator_->model().noise_std(), noise_generator_);
    windows.push_back({&t, ids, frame, history, noisy, fraction});
  }
  return windows;
}

TrainingBatch Trainer::batch_of(const std::vector<LossWindow>& windows, int k) const {
  std::vector<gnn::GraphInput> graphs;
  std::vector<torch::Tensor> targets, masks, fraction_targets;
  for (const auto& w : windows) {
    const gnn::Trajectory& t = *w.trajectory;
    const int64_t target_frame = w.frame + 1 + k;
    auto next = t.position[target_frame].index_select(0, w.ids);
    graphs.push_back(simulator_->encode({w.history, w.fraction, t.material, t.boundary}));
    // The first frame's input is the noisy one: its target undoes the velocity noise (GNS's);
    // a later frame's is the model's own forecast, whose target reaches the recorded frame.
    targets.push_back(simulator_->normalise_acceleration(
        k == 0 ? gnn::noisy_target_acceleration(w.clean_history, w.history, next)
               : gnn::target_acceleration(w.history, next)));
    fraction_targets.push_back(simulator_->normalise_fraction_change(
        t.oil_fraction[target_frame].index_select(0, w.ids) - w.fraction));
    masks.push_back(t.active[target_frame].index_select(0, w.ids));
  }
  const torch::Device device = simulator_->device();
  return {gnn::join_graphs(graphs), torch::cat(targets).to(device), torch::cat(masks).to(device),
          torch::cat(fraction_targets).to(device)};
}

torch::Tensor Trainer::unrolled_loss(std::vector<LossWindow> windows, const TrainingBatch& first) {
  const int frames = config_.training.loss_frames;
  TrainingBatch batch = first;
  torch::Tensor total;
  for (int k = 0;; ++k) {
    const gnn::ModelOutput output =
        simulator_->model().forward(batch.graph, objective_->forward_options(batch, state_.step));
    const torch::Tensor value = objective_->evaluate(output, batch).total;
    total = k == 0 ? value : total + value;
    if (k + 1 == frames) break;
    // Each window's next input: its forecast position, with gradient through it (the windows'
    // fluid rows follow each other in the joined graph, in window order).
    const auto acceleration = simulator_->denormalise_acceleration(
        output.acceleration.index({batch.graph.fluid}).to(torch::kCPU));
    int64_t row = 0;
    for (auto& w : windows) {
      const int64_t n = w.ids.size(0);
      const auto last = w.history.select(1, gnn::kWindow - 1);
      const auto next = last + (last - w.history.select(1, gnn::kWindow - 2)) +
                        acceleration.slice(0, row, row + n);
      w.history = torch::cat({w.history.slice(1, 1), next.unsqueeze(1)}, 1);
      // The oil fraction is the recording's: the unroll is for the positions' drift.
      w.fraction = w.trajectory->oil_fraction[w.frame + 1 + k].index_select(0, w.ids);
      row += n;
    }
    batch = batch_of(windows, k + 1);
  }
  return total / double(frames);
}

torch::Tensor Trainer::loss(const TrainingBatch& batch) {
  const gnn::ModelOutput output =
      simulator_->model().forward(batch.graph, objective_->forward_options(batch, state_.step));
  return objective_->evaluate(output, batch).total;
}

void Trainer::load_teacher() {
  if (options_.teacher.empty()) return;
  // The model's registry entry names its objective, whose entry says whether it distils.
  const std::string model = config_.model_json.value("model", std::string("?"));
  const gnn::ObjectiveEntry objective = gnn::model_objective(model);
  if (!objective.distils)
    throw common::ConfigError(config_.model_file, "/model",
                              "--teacher distils a student whose objective distils; this config "
                              "trains " +
                                  model + " with " + objective.name + ", which does not");
  // The teacher is the same model at another size (docs/models.md, "Teacher, student and FRKD").
  auto loaded = gnn::load_checkpoint(options_.teacher, model);
  gnn::check_data_fits(loaded.data, metadata_, options_.teacher);
  teacher_ = loaded.simulator->model_ptr();
  teacher_record_ = {{"path", fs::absolute(options_.teacher).lexically_normal().string()},
                     {"checksum", loaded.payload_checksum}};
  teacher_->eval();  // batch normalisation on its running statistics
  for (auto& p : teacher_->parameters()) p.set_requires_grad(false);
}

void Trainer::validate(double& one_step_loss, double& rollout_mse, double& standalone_skill) {
  torch::NoGradGuard no_grad;
  // Batch normalisation (PAGATNet) uses its running statistics here, as in a rollout.
  simulator_->model().eval();
  const auto& c = config_.training;
  double sum = 0;
  int count = 0;
  // Fixed frames spread over the valid trajectories, without noise: the same set every time.
  const int world = options_.parallel ? options_.parallel->world() : 1;
  const int rank = options_.parallel ? options_.parallel->rank() : 0;
  for (int k = 0; k < c.validation_samples; ++k) {
    if (k % world != rank) continue;  // another rank's sample
    const auto& t = valid_[size_t(k) % valid_.size()];
    const int64_t span = t.frames() - 1 - gnn::kWindow;
    const int64_t frame =
        gnn::kWindow - 1 +
        (span * (k / int(valid_.size()) + 1)) / (c.validation_samples / int(valid_.size()) + 2);
    auto ids = gnn::active_ids(t, frame);
    auto history = gnn::position_history(t, frame, ids, metadata_.frame_dt);
    gnn::FrameNodes nodes{history, t.oil_fraction[frame].index_select(0, ids), t.material,
                          t.boundary};
    auto target = simulator_->normalise_acceleration(
        gnn::target_acceleration(history, t.position[frame + 1].index_select(0, ids)));
    auto keep = t.active[frame + 1].index_select(0, ids);
    sum +=
        (simulator_->predict_normalised(nodes) - target).pow(2).index({keep}).mean().item<double>();
    ++count;
  }
  if (options_.parallel) {
    std::vector<double> totals{sum, double(count)};
    options_.parallel->sum(totals);
    sum = totals[0];
    count = int(totals[1]);
  }
  one_step_loss = sum / count;
  const auto& t = valid_.front();
  const int64_t frames = std::min<int64_t>(c.validation_rollout_frames, t.frames() - gnn::kWindow);
  auto r = gnn::rollout(*simulator_, t, gnn::kWindow - 1, frames, metadata_.frame_dt);
  auto last = r.position[frames];
  auto truth = t.position[gnn::kWindow - 1 + frames];
  rollout_mse = (last - truth).pow(2).index({r.active[frames]}).mean().item<double>();
  // The standalone score best.pt is kept by (rank 0 keeps it).
  standalone_skill = std::nan("");
  if (c.best_checkpoint_trajectories > 0 && writes()) {
    double skill = 0;
    int scored = 0;
    for (size_t k = 0; k < std::min(valid_.size(), size_t(c.best_checkpoint_trajectories)); ++k) {
      const double s = gnn::standalone_footprint_skill(*simulator_, valid_[k], metadata_);
      if (std::isnan(s)) continue;
      skill += s;
      ++scored;
    }
    if (scored > 0) standalone_skill = skill / scored;
  }
}

void Trainer::keep_if_best(double standalone_skill) {
  if (std::isnan(standalone_skill) || !(standalone_skill > best_skill_) || !writes()) return;
  best_skill_ = standalone_skill;
  save(best_path(options_.out_dir).string());
  common::write_file_atomically(
      best_record_path(options_.out_dir),
      nlohmann::json{
          {"step", state_.step},
          {"valid_standalone_fss", standalone_skill},
          {"trajectories",
           std::min(valid_.size(), size_t(config_.training.best_checkpoint_trajectories))},
          {"note",
           "best.pt: the checkpoint whose standalone forecasts of the first `trajectories` valid "
           "trajectories had the highest mean oil-footprint Fractions Skill Score at 20 cm, 1 s "
           "and 2 s after each one's first full-history frame (gnn/eval/standalone_skill.h)"}}
              .dump(2) +
          "\n");
}

void Trainer::save(const std::string& path) {
  std::ostringstream s;
  s << sampler_;
  state_.sampler_state = s.str();
  state_.noise_generator_state = noise_generator_.get_state();
  gnn::save_checkpoint(path, *simulator_, gnn::describe_data(metadata_), state_, optimizer_.get());
}

void Trainer::write_loss_plot() const {
  std::ifstream in((fs::path(options_.out_dir) / "log.csv").string());
  std::string line;
  std::getline(in, line);
  common::PlotSeries train{"training loss", {}, {}}, valid{"valid one-step", {}, {}};
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
    if (cells.size() < 2) continue;
    train.x.push_back(std::stod(cells[0]));
    train.y.push_back(std::stod(cells[1]));
    if (cells.size() > 5 && !cells[5].empty()) {
      valid.x.push_back(std::stod(cells[0]));
      valid.y.push_back(std::stod(cells[5]));
    }
  }
  common::write_line_plot((fs::path(options_.out_dir) / "loss.svg").string(),
                          "Training of " + simulator_->model().name(), "step",
                          "MSE of normalised acceleration", {train, valid}, true);
}

double Trainer::run() {
  // A run folder made by this run and left without a checkpoint holds nothing to resume: it is
  // removed when training fails (a full disk once left an empty config.json and log.csv).
  const bool new_folder = !fs::exists(options_.out_dir);
  try {
    return train_steps();
  } catch (...) {
    std::error_code ec;
    if (writes() && new_folder && !fs::exists(checkpoint_path(options_.out_dir), ec))
      fs::remove_all(options_.out_dir, ec);
    throw;
  }
}

// The run folder with its log.csv (a resumed run's cut back to its checkpoint's step) and, for a
// new run, config.json. Returns the log file.
std::string Trainer::open_run_folder() const {
  if (!writes()) return "";  // rank 0 writes the run folder
  std::error_code ec;
  fs::create_directories(options_.out_dir, ec);
  if (ec)
    throw common::OutputPathError("--out " + options_.out_dir + ": cannot create: " + ec.message());
  const std::string log_file = (fs::path(options_.out_dir) / "log.csv").string();
  if (options_.resume && fs::exists(log_file)) {
    truncate_log(log_file, state_.step);
  } else {
    common::write_file_atomically(log_file, std::string(kLogHeader) + "\n");
    common::write_file_atomically(
        fs::path(options_.out_dir) / "config.json",
        nlohmann::json{
            {"training", config_.training_json},
            {"model", simulator_->model().config()},
            {"data", data_description_},
            {"teacher", options_.teacher},
            {"teacher_checksum",
             teacher_record_.is_object() ? teacher_record_.at("checksum") : nlohmann::json()}}
                .dump(2) +
            "\n");
  }
  return log_file;
}

// Throws common::Interrupted when Ctrl-C or SIGTERM came, saying what the run folder keeps:
// `kept_step` is the step of its checkpoint, or -1 before the first (run() then removes a new
// run's folder).
void Trainer::stop_if_requested(int64_t kept_step) const {
  common::throw_if_stopped(options_.stop, [&] {
    return "at step " + std::to_string(state_.step) + " of " +
           std::to_string(config_.training.steps) + "; " +
           (kept_step < 0 ? "no checkpoint was written yet, so the new run folder " +
                                options_.out_dir + " is removed"
                          : checkpoint_path(options_.out_dir) + " keeps step " +
                                std::to_string(kept_step) + " (--resume goes on from there)");
  });
}

// One Adam step at learning rate `lr` on a sampled batch; returns its loss.
double Trainer::gradient_step(double lr) {
  for (auto& group : optimizer_->param_groups())
    static_cast<torch::optim::AdamOptions&>(group.options()).lr(lr);
  auto windows = sample_windows();
  const TrainingBatch batch = batch_of(windows, 0);
  optimizer_->zero_grad();
  auto l =
      config_.training.loss_frames > 1 ? unrolled_loss(std::move(windows), batch) : loss(batch);
  l.backward();
  double value = l.item<double>();
  if (DataParallel* parallel = options_.parallel) {
    // The loss is a mean over the share's loss terms (particles): weighted by their count, the
    // summed gradients and loss are those of the mean over the whole batch.
    const auto start = std::chrono::steady_clock::now();
    const double terms = double(batch.mask.sum().item<int64_t>());
    std::vector<double> totals{terms, value * terms};
    parallel->sum(totals);
    parallel->sum_weighted_gradients(simulator_->model().parameters(), terms / totals[0]);
    value = totals[1] / totals[0];
    collective_s_ +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ++collective_steps_;
  }
  optimizer_->step();
  if (options_.parallel) {
    // Batch normalisation's running statistics saw only this rank's share: rank 0's are kept,
    // as DistributedDataParallel does.
    const auto buffers = simulator_->model().buffers();
    if (!buffers.empty()) options_.parallel->broadcast_from_first(buffers);
  }
  ++state_.step;
  if (!std::isfinite(value))
    throw std::runtime_error(options_.config_file + ": training diverged: the loss is " +
                             std::to_string(value) + " at step " + std::to_string(state_.step) +
                             " (a lower /lr_max may train)");
  return value;
}

double Trainer::train_steps() {
  const auto& c = config_.training;
  if (state_.step >= c.steps && options_.log)
    *options_.log << "note: the run has trained its " << c.steps
                  << " steps already; nothing to do (raise /steps to go on)\n";
  const std::string log_file = open_run_folder();
  std::ostringstream log;  // one line per log step, appended (and checked) as it completes
  log << std::setprecision(9);
  std::unique_ptr<common::ProgressReporter> progress;
  if (options_.log)
    progress = std::make_unique<common::ProgressReporter>(
        *options_.log, options_.terminal, c.steps - state_.step,
        "training to step " + std::to_string(c.steps));
  const int64_t first_step = state_.step;
  const auto start = std::chrono::steady_clock::now();
  const double elapsed_before = state_.elapsed_s;
  auto elapsed = [&] {
    return elapsed_before +
           std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  double loss_sum = 0, last_loss = 0;
  int loss_count = 0;
  double window_start = elapsed();
  simulator_->model().train();
  // The step the run folder's checkpoint holds (none yet for a new run), for the interruption's
  // message: an interrupted run keeps its last checkpoint, and --resume goes on from it.
  int64_t kept_step = options_.resume ? state_.step : -1;
  while (state_.step < c.steps) {
    stop_if_requested(kept_step);
    const double lr = learning_rate(c, state_.step);
    const double value = gradient_step(lr);
    loss_sum += value;
    ++loss_count;
    const bool validate_now = state_.step % c.validate_every == 0 || state_.step == c.steps;
    if (state_.step % c.log_every == 0 || validate_now) {
      last_loss = loss_sum / loss_count;
      const double now = elapsed();
      log << state_.step << "," << last_loss << "," << lr << "," << now << ","
          << loss_count / std::max(now - window_start, 1e-9) << ",";
      if (validate_now) {
        double one_step = 0, rollout = 0, skill = 0;
        validate(one_step, rollout, skill);
        simulator_->model().train();
        log << one_step << "," << rollout << ",";
        if (!std::isnan(skill)) log << skill;
        keep_if_best(skill);
      } else {
        log << ",,";
      }
      log << "\n";
      if (writes()) common::append_to_file(log_file, log.str());
      log.str("");
      if (progress) {
        std::ostringstream d;
        d << std::setprecision(3) << "loss " << last_loss << " lr " << lr << " "
          << loss_count / std::max(now - window_start, 1e-9) << " steps/s";
        progress->update(state_.step - first_step, d.str());
      }
      loss_sum = 0;
      loss_count = 0;
      window_start = elapsed();
    }
    if (state_.step % c.checkpoint_every == 0 || state_.step == c.steps) {
      state_.elapsed_s = elapsed();
      log.flush();
      if (writes()) {
        save(checkpoint_path(options_.out_dir));
        write_loss_plot();
      }
      kept_step = state_.step;
    }
  }
  if (progress) progress->finish("step " + std::to_string(state_.step));
  if (options_.parallel && collective_steps_ > 0) {
    int64_t floats = 0;
    for (const auto& p : simulator_->model().parameters()) floats += p.numel();
    // The allreduce alone, every rank ready (the step's figure includes waiting for the slower
    // rank's share); all ranks take part. Read by scripts/distributed_bench.py.
    const double alone = options_.parallel->time_allreduce(floats, 20);
    if (options_.log)
      *options_.log << "data-parallel: gradient allreduce of " << floats << " floats over "
                    << options_.parallel->world()
                    << " ranks: " << 1e3 * collective_s_ / double(collective_steps_)
                    << " ms a step over " << collective_steps_ << " steps, waiting included; "
                    << 1e3 * alone << " ms alone\n";
  }
  return last_loss;
}

}  // namespace train
