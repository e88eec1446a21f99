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
  // What the model must return besides the acceleration (latents for distillation).
  virtual ForwardOptions forward_options() const { return {}; }
  virtual ObjectiveValue evaluate(const ModelOutput& output, const TrainingBatch& batch) const = 0;
};

// MODELS.md's L_acc: mean squared error of the normalised acceleration over the fluid particles
// that are active in the next frame ("acc"), plus `fraction_weight` times the mean squared error
// of the normalised change of the oil fraction over the same particles ("frac"): every model is a
// surrogate of both what MTDF-SPH moves and how it moves oil between particles.
class AccelerationMse : public TrainingObjective {
 public:
  explicit AccelerationMse(double fraction_weight = 1.0) : fraction_weight_(fraction_weight) {}
  std::string name() const override { return "acceleration_mse"; }
  ObjectiveValue evaluate(const ModelOutput& output, const TrainingBatch& batch) const override;

 private:
  double fraction_weight_;
};

// The objective a model is trained with (acceleration and oil-fraction MSE for GNS and DPI-Nets);
// `fraction_weight` is the training config's oil_fraction_loss_weight.
std::unique_ptr<TrainingObjective> make_objective(const GraphModel& model, double fraction_weight);

}  // namespace gnn
