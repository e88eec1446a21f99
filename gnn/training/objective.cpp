#include "gnn/training/objective.h"

#include <stdexcept>

namespace gnn {

ObjectiveValue AccelerationMse::evaluate(const ModelOutput& output,
                                         const TrainingBatch& batch) const {
  const auto predicted = output.acceleration.index({batch.graph.fluid});
  if (predicted.sizes() != batch.target.sizes())
    throw std::invalid_argument("acceleration_mse: the model predicts " +
                                std::to_string(predicted.size(0)) + " fluid rows, the batch has " +
                                std::to_string(batch.target.size(0)) + " targets");
  auto acc = (predicted - batch.target).pow(2).index({batch.mask}).mean();
  return {acc, {{"acc", acc}}};
}

std::unique_ptr<TrainingObjective> make_objective(const GraphModel&) {
  return std::make_unique<AccelerationMse>();
}

}  // namespace gnn
