#pragma once
// The training loop of spill-train: samples windows of random frames of random training
// trajectories, adds the random-walk noise, optionally pushes the window forward with the model
// itself, and takes Adam steps on the model's training objective (gnn/training/objective.h: the
// MSE of the normalised acceleration over fluid particles for GNS), with the learning rate of
// MODELS.md. The model trains in train() mode and is validated in eval() mode. It validates
// periodically (one-step loss on fixed frames of the valid split, and a short rollout), logs to
// RUN/log.csv and RUN/loss.svg, and writes RUN/last.pt atomically. Resuming from last.pt continues
// the same random streams, so on one thread a resumed run reproduces the uninterrupted run's log
// row for row.

#include <iosfwd>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "gnn/data/dataset.h"
#include "gnn/models/learned_simulator.h"
#include "gnn/training/checkpoint.h"
#include "gnn/training/objective.h"
#include "train/training_config.h"

namespace train {

struct TrainerOptions {
  std::string config_file;
  std::vector<std::string> overrides;
  std::string data_dir;
  std::string out_dir;
  bool resume = false;
  torch::Device device = torch::kCPU;  // where the model trains (the data pipeline stays on CPU)
  std::ostream* log = nullptr;         // progress; null for none
  bool terminal = false;
};

using gnn::TrainingBatch;

class Trainer {
 public:
  explicit Trainer(TrainerOptions options);
  // Trains up to the configured step count; returns the final training loss (last log row).
  double run();
  // The objective's total loss of one batch (with autograd).
  torch::Tensor loss(const TrainingBatch& batch);
  TrainingBatch sample_batch();
  gnn::LearnedSimulator& simulator() { return *simulator_; }
  int64_t step() const { return state_.step; }

 private:
  double train_steps();  // run() without the clean-up of a failed new run folder
  void validate(double& one_step_loss, double& rollout_mse);
  void save(const std::string& path);
  void write_loss_plot() const;

  TrainerOptions options_;
  ResolvedConfig config_;
  gnn::DatasetMetadata metadata_;
  std::vector<gnn::Trajectory> train_, valid_;
  std::unique_ptr<gnn::LearnedSimulator> simulator_;
  std::unique_ptr<gnn::TrainingObjective> objective_;
  std::unique_ptr<torch::optim::Adam> optimizer_;
  gnn::TrainingState state_;
  std::mt19937_64 sampler_;
  torch::Generator noise_generator_;
};

}  // namespace train
