#include "gnn/training/objective.h"

#include <stdexcept>

#include "gnn/models/pagat_model.h"
#include "gnn/training/pagat_objective.h"

namespace gnn {

ObjectiveValue AccelerationMse::evaluate(const ModelOutput& output,
                                         const TrainingBatch& batch) const {
  const auto predicted = output.acceleration.index({batch.graph.fluid});
  if (predicted.sizes() != batch.target.sizes())
    throw std::invalid_argument("acceleration_mse: the model predicts " +
                                std::to_string(predicted.size(0)) + " fluid rows, the batch has " +
                                std::to_string(batch.target.size(0)) + " targets");
  auto acc = (predicted - batch.target).pow(2).index({batch.mask}).mean();
  if (!batch.fraction_target.defined() || fraction_weight_ == 0) return {acc, {{"acc", acc}}};
  const auto change = output.oil_fraction_change.index({batch.graph.fluid});
  if (change.sizes() != batch.fraction_target.sizes())
    throw std::invalid_argument("acceleration_mse: the model predicts " +
                                std::to_string(change.size(0)) +
                                " oil fraction changes, the batch has " +
                                std::to_string(batch.fraction_target.size(0)) + " targets");
  auto frac = (change - batch.fraction_target).pow(2).index({batch.mask}).mean();
  return {acc + fraction_weight_ * frac, {{"acc", acc}, {"frac", frac}}};
}

std::unique_ptr<TrainingObjective> make_objective(GraphModel& model,
                                                  const ObjectiveSettings& settings,
                                                  std::shared_ptr<GraphModel> teacher) {
  if (auto* pagat = dynamic_cast<PagatModel*>(&model))
    return std::make_unique<PagatObjective>(*pagat, settings, std::move(teacher));
  if (teacher)
    throw std::invalid_argument("distillation needs a PAGATNet student, not " + model.name());
  return std::make_unique<AccelerationMse>(settings.oil_fraction_loss_weight);
}

}  // namespace gnn
