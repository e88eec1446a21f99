#pragma once
// The training loop of spill-train: samples windows of random frames of random training
// trajectories, adds the random-walk noise, optionally pushes the window forward with the model
// itself, and takes Adam steps on the model's training objective (gnn/training/objective.h: the
// MSE of the normalised acceleration over fluid particles for GNS), optionally averaged over a
// few frames the model forecasts in turn (loss_frames), with the learning rate of
// docs/models.md. The model trains in train() mode and is validated in eval() mode. It validates
// periodically (one-step loss on fixed frames of the valid split, and a short rollout), logs to
// RUN/log.csv and RUN/loss.svg, and writes RUN/last.pt atomically. Resuming from last.pt continues
// the same random streams, so on one thread a resumed run reproduces the uninterrupted run's log
// row for row.

#include <atomic>
#include <functional>
#include <iosfwd>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "gnn/data/dataset.h"
#include "gnn/models/learned_simulator.h"
#include "gnn/training/checkpoint.h"
#include "gnn/training/objective.h"
#include "train/data_parallel.h"
#include "train/training_config.h"

namespace train {

struct TrainerOptions {
  std::string config_file;
  std::vector<std::string> overrides;
  std::string data_dir;  // the dataset folder (--data) of Trainer(options)
  std::string out_dir;
  bool resume = false;
  // A PAGATNet checkpoint to distil the model from (a PAGATNet student); empty: none.
  std::string teacher;
  torch::Device device = torch::kCPU;  // where the model trains (the data pipeline stays on CPU)
  std::ostream* log = nullptr;         // progress; null for none
  bool terminal = false;
  // Set by Ctrl-C or SIGTERM (common/stop_signals.h): the run stops before its next step and
  // keeps its last checkpoint (a new run without one is removed); null: never.
  const std::atomic<bool>* stop = nullptr;
  // The process group of a data-parallel launch (train/data_parallel.h); null: one process.
  // Every rank draws the same global batches from the seeded streams and trains on its share
  // (windows b with b mod world = rank); the gradients are summed weighted by each share's loss
  // terms, so a step is the one-process step on the whole batch. Rank 0 alone writes the run
  // folder and prints; the checkpoint's streams are every rank's, so a run resumes at any world
  // size.
  DataParallel* parallel = nullptr;
};

using gnn::TrainingBatch;

// One sampled training window, carried through the loss frames: the particles present through
// all of it, the frame its first loss frame starts from, and its current input.
struct LossWindow {
  const gnn::Trajectory* trajectory = nullptr;
  torch::Tensor ids;
  int64_t frame = 0;            // the first loss frame's target is frame + 1
  torch::Tensor clean_history;  // [n, kWindow, 3] before the noise (first loss frame only)
  torch::Tensor history;        // [n, kWindow, 3] the model's input
  torch::Tensor fraction;       // [n]
};

// What a run trains and validates on.
struct TrainingData {
  gnn::DatasetMetadata metadata;
  std::vector<gnn::Trajectory> train, valid;
  nlohmann::json description;  // RUN/config.json's "data": the folder, or how it was simulated
};

// A dataset folder's metadata.json, train.h5 and valid.h5.
TrainingData read_training_data(const std::string& dir);

class Trainer {
 public:
  // Trains on the dataset folder options.data_dir.
  explicit Trainer(TrainerOptions options);
  // Trains on what `load_data` returns. It is called once, after the training config and the
  // run folder (a new run's, or --resume's checkpoint) were checked, so that those fail before a
  // long load such as simulating the data (train/scene_data.h).
  Trainer(TrainerOptions options, const std::function<TrainingData()>& load_data);
  // Trains up to the configured step count; returns the final training loss (last log row).
  double run();
  // The objective's total loss of one batch (with autograd).
  torch::Tensor loss(const TrainingBatch& batch);
  // This process's share of the next global batch (all of it without a process group), as the
  // batch of its first loss frame.
  TrainingBatch sample_batch() { return batch_of(sample_windows(), 0); }
  // This process's windows of the next global batch, pushed forward and with the noise added.
  std::vector<LossWindow> sample_windows();
  // The batch of loss frame `k` of `windows`: their current input, the recorded frame after it.
  TrainingBatch batch_of(const std::vector<LossWindow>& windows, int k) const;
  // The loss averaged over the config's loss_frames, each frame's input after the first the
  // model's forecast of the frame before (with autograd); `first` is batch_of(windows, 0).
  torch::Tensor unrolled_loss(std::vector<LossWindow> windows, const TrainingBatch& first);
  gnn::LearnedSimulator& simulator() { return *simulator_; }
  int64_t step() const { return state_.step; }

 private:
  double train_steps();  // run() without the clean-up of a failed new run folder
  bool writes() const { return !options_.parallel || options_.parallel->rank() == 0; }
  double gradient_step(double lr);
  std::string open_run_folder() const;
  void stop_if_requested(int64_t kept_step) const;
  // `standalone_skill`: the score best.pt is kept by; NaN when off or not scored.
  void validate(double& one_step_loss, double& rollout_mse, double& standalone_skill);
  // Saves best.pt and best.json when `standalone_skill` beats the best so far.
  void keep_if_best(double standalone_skill);
  void save(const std::string& path);
  void write_loss_plot() const;

  TrainerOptions options_;
  ResolvedConfig config_;
  gnn::DatasetMetadata metadata_;
  std::vector<gnn::Trajectory> train_, valid_;
  nlohmann::json data_description_;
  std::unique_ptr<gnn::LearnedSimulator> simulator_;
  std::unique_ptr<gnn::TrainingObjective> objective_;
  // --teacher: the frozen PAGATNet a student is distilled from (null: none).
  std::shared_ptr<gnn::GraphModel> teacher_;
  nlohmann::json teacher_record_;  // {"path", "checksum"} of teacher_; null without one
  void load_teacher();
  void check_resumed_teacher(const std::string& last);
  void take_data(TrainingData data);
  void resume_model(const std::string& last);
  void start_model();
  void choose_objective();
  std::unique_ptr<torch::optim::Adam> optimizer_;
  gnn::TrainingState state_;
  std::mt19937_64 sampler_;
  torch::Generator noise_generator_;
  double best_skill_ = -1e300;  // best.json's score (resumed with the run)
  double collective_s_ = 0;     // time in the data-parallel sums and gradient allreduce
  int64_t collective_steps_ = 0;
};

}  // namespace train
