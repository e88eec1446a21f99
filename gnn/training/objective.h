#pragma once
// The training objective: what a training step minimises, given the model's output for a batch.
// A pluggable piece, so the trainer's loop does not change when a model brings terms of its own
// (PAGATNet: the attention-class cross-entropy and, for a student, distillation against a frozen
// teacher, L = l1 L_acc + l2 L_att + l3 L_KD). Every term is reported by name for the log.

#include <torch/torch.h>

#include <map>
#include <memory>
#include <string>

#include "gnn/models/graph_model.h"

namespace gnn {

// Sampled training frames, encoded as one graph.
struct TrainingBatch {
  GraphInput graph;
  torch::Tensor target;  // [fluid rows of the graph, 3] normalised acceleration
  torch::Tensor mask;    // [fluid rows] bool: in the loss (active in the next frame)
};

struct ObjectiveValue {
  torch::Tensor total;                         // the scalar to minimise (with autograd)
  std::map<std::string, torch::Tensor> terms;  // each unweighted term, by name ("acc", ...)
};

class TrainingObjective {
 public:
  virtual ~TrainingObjective() = default;
  virtual std::string name() const = 0;
  // What the model must return besides the acceleration (latents for distillation).
  virtual ForwardOptions forward_options() const { return {}; }
  virtual ObjectiveValue evaluate(const ModelOutput& output, const TrainingBatch& batch) const = 0;
};

// MODELS.md's L_acc: mean squared error of the normalised acceleration over the fluid particles
// that are active in the next frame.
class AccelerationMse : public TrainingObjective {
 public:
  std::string name() const override { return "acceleration_mse"; }
  ObjectiveValue evaluate(const ModelOutput& output, const TrainingBatch& batch) const override;
};

// The objective a model is trained with (acceleration MSE for GNS).
std::unique_ptr<TrainingObjective> make_objective(const GraphModel& model);

}  // namespace gnn
