#pragma once
// Checkpoints: one `*.pt` file (a LibTorch archive) with the model's parameters, the optimiser
// state, the training step and elapsed time, the state of both random generators (sampling and
// noise), the normalisation statistics, the resolved model and training configs, and a
// description of the data it was trained on (dimension, particle radius, connectivity radius,
// bounds, particle types). Written to a temporary file and renamed, so a crash never leaves a
// half checkpoint. A model is always rebuilt from the config stored with its weights.

#include <torch/torch.h>

#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>

#include "common/exit_codes.h"
#include "gnn/data/dataset.h"
#include "gnn/models/graph_model.h"
#include "gnn/models/learned_simulator.h"

namespace gnn {

class CheckpointError : public common::InputError {
 public:
  using common::InputError::InputError;
};

struct TrainingState {
  int64_t step = 0;
  double elapsed_s = 0;
  std::string sampler_state;            // std::mt19937_64 in text form
  torch::Tensor noise_generator_state;  // at::Generator::get_state()
  nlohmann::json training_config;
  // The teacher a student is distilled from: {"path", "checksum"} (the teacher's
  // LoadedCheckpoint::payload_checksum), so that --resume can check it is given the same one;
  // null for a run without a teacher (and for checkpoints written before it was recorded).
  nlohmann::json teacher;
};

// What a checkpoint says about the data it was trained on.
nlohmann::json describe_data(const DatasetMetadata& metadata);

void save_checkpoint(const std::string& path, LearnedSimulator& simulator,
                     const nlohmann::json& data, const TrainingState& state,
                     torch::optim::Optimizer* optimizer);

struct LoadedCheckpoint {
  std::unique_ptr<LearnedSimulator> simulator;
  nlohmann::json data;
  TrainingState state;
  std::string payload_checksum;  // FNV-1a of the weights and normalisation (hex)
};

// Loads the model (rebuilt from its stored config); with `optimizer` also its state.
// `expected_model`, when given, must match the stored model name. Errors name the file.
LoadedCheckpoint load_checkpoint(const std::string& path,
                                 const std::optional<std::string>& expected_model = std::nullopt);
void load_optimizer_state(const std::string& path, torch::optim::Optimizer& optimizer);

// Writes a copy of the checkpoint at `from` without its optimiser state, for sharing and inference
// (a third of the size with Adam): it loads, rolls out and teaches (`--teacher`) like the
// original, but training cannot resume from it. An existing `to` is refused (it may be another
// run's last.pt, which the copy would make unresumable), unless `replace` is set and `to` is
// itself a checkpoint other than `from`; the copy then replaces it atomically.
void write_weights_only(const std::string& from, const std::string& to, bool replace);

// Throws CheckpointError when the data does not fit the checkpoint (dimension, particle types,
// particle radius or connectivity radius differ).
void check_data_fits(const nlohmann::json& checkpoint_data, const DatasetMetadata& metadata,
                     const std::string& checkpoint_path);

}  // namespace gnn
