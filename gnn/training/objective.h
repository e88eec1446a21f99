#pragma once
// The training objective: what a training step minimises, given the model's output for a batch.
// A pluggable piece, so the trainer's loop does not change when a model brings terms of its own
// (PAGATNet: the attention-class cross-entropy and, for a student, distillation against a frozen
// teacher, L = l1 L_acc + l2 L_att + l3 L_KD). Every term is reported by name for the log.
//
// Objectives are registered as the simulator's pressure solvers are: each declares its settings
// (a struct with describe()) and its registry entry in its own file pair, objective_registry.cpp
// lists the entries, and a model's registry entry names the objective it trains with
// (gnn/models/model_registry.h). The training config holds every objective's settings as
// sections without knowing their types (objective_settings.h).

#include <torch/torch.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "common/config_section.h"
#include "gnn/models/graph_model.h"
#include "gnn/training/objective_settings.h"

namespace gnn {

// Sampled training frames, encoded as one graph.
struct TrainingBatch {
  GraphInput graph;
  torch::Tensor target;           // [fluid rows of the graph, 3] normalised acceleration
  torch::Tensor mask;             // [fluid rows] bool: in the loss (active in the next frame)
  torch::Tensor fraction_target;  // [fluid rows] normalised change of the oil fraction
};

struct ObjectiveValue {
  torch::Tensor total;                         // the scalar to minimise (with autograd)
  std::map<std::string, torch::Tensor> terms;  // each unweighted term, by name ("acc", ...)
};

class TrainingObjective {
 public:
  virtual ~TrainingObjective() = default;
  virtual std::string name() const = 0;
  // What the model must return besides the acceleration for `batch` at training step `step`
  // (latents for distillation; a distilling objective runs its teacher on the batch here).
  virtual ForwardOptions forward_options(const TrainingBatch& /*batch*/, int64_t /*step*/) {
    return {};
  }
  virtual ObjectiveValue evaluate(const ModelOutput& output, const TrainingBatch& batch) const = 0;
};

// What an objective is made from.
struct ObjectiveInputs {
  // Every objective's settings, each under its section key (the training config's sections;
  // the defaults until read over).
  common::ConfigSections settings = objective_sections();
  int64_t steps = 1;  // the run's length (schedules over the run, such as PAGATNet's generator)
  std::shared_ptr<GraphModel> teacher;  // frozen, to distil the model from; null: none
};

// How an objective is registered (one line in objective_registry.cpp): everything about it that
// the trainer needs, so nothing else tests an objective's or a model's name.
struct ObjectiveEntry {
  std::string name;  // what a model's registry entry names (ModelEntry::objective)
  // Its settings, declared beside its code, each under its training-config key; it may also
  // read another objective's section (PAGATNet's L_acc is acceleration_mse's) and lists it too.
  std::vector<common::ConfigSectionEntry> sections;
  // Whether it trains a student against a frozen teacher (ObjectiveInputs::teacher,
  // spill-train --teacher); the others refuse a teacher.
  bool distils = false;
  // Throws std::invalid_argument when the model or the teacher does not fit the objective.
  std::unique_ptr<TrainingObjective> (*make)(GraphModel& model, const ObjectiveInputs& inputs);
};

// Every registered objective, in the registry's order.
std::vector<ObjectiveEntry> objective_entries();
// The entry of `name`. Throws std::invalid_argument for an unknown name.
ObjectiveEntry objective_entry(const std::string& name);
// The entry of the objective that the registered model `model_name` trains with.
ObjectiveEntry model_objective(const std::string& model_name);

// The objective `model` trains with (its registry entry's), made from `inputs`. A teacher for a
// model whose objective does not distil is std::invalid_argument.
std::unique_ptr<TrainingObjective> make_objective(GraphModel& model, const ObjectiveInputs& inputs);

}  // namespace gnn
