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
  // What the model must return besides the acceleration for `batch` at training step `step`
  // (latents for distillation; a distilling objective runs its teacher on the batch here).
  virtual ForwardOptions forward_options(const TrainingBatch& /*batch*/, int64_t /*step*/) {
    return {};
  }
  virtual ObjectiveValue evaluate(const ModelOutput& output, const TrainingBatch& batch) const = 0;
};

// docs/models.md's L_acc: mean squared error of the normalised acceleration over fluid particles
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

// The weights and settings of the objectives (the training config's keys of the same names).
struct ObjectiveSettings {
  double oil_fraction_loss_weight = 1.0;
  // PAGATNet: L = l1 L_acc + l2 L_att + l3 L_KD, L_KD = L_T-S + beta L_MKD.
  double acceleration_loss_weight = 1.0;  // l1
  double attention_loss_weight = 0.1;     // l2
  double distillation_loss_weight = 1.0;  // l3
  double distillation_beta = 1.0;         // beta
  double generator_strength = 0.5;        // lambda at step 0, falling linearly to 0 ...
  double generator_until = 0.25;          // ... at this fraction of the run, then 0
  int distillation_stride = 2;            // student block k pairs with teacher block s (k+1) - 1
  int64_t steps = 1;                      // the run's length (the generator's schedule)
};

// The objective a model is trained with: acceleration and oil-fraction MSE for GNS and DPI-Nets;
// PAGATNet's weighted sum with the attention-class loss, and distillation against `teacher`
// (frozen; null: none) for a student.
std::unique_ptr<TrainingObjective> make_objective(GraphModel& model,
                                                  const ObjectiveSettings& settings,
                                                  std::shared_ptr<GraphModel> teacher = nullptr);

}  // namespace gnn
