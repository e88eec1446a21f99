#include "gnn/training/acceleration_mse.h"

#include <stdexcept>

namespace gnn {

common::ConfigSectionEntry AccelerationMse::section() {
  return common::ConfigSectionEntry::of<AccelerationMseSettings>(
      kSection, "acceleration and oil fraction MSE (every model's L_acc)");
}

ObjectiveEntry AccelerationMse::entry() {
  return {"acceleration_mse",
          {section()},
          /*distils=*/false,
          [](GraphModel&, const ObjectiveInputs& inputs) -> std::unique_ptr<TrainingObjective> {
            return std::make_unique<AccelerationMse>(
                inputs.settings.get<AccelerationMseSettings>(kSection));
          }};
}

ObjectiveValue AccelerationMse::evaluate(const ModelOutput& output,
                                         const TrainingBatch& batch) const {
  const auto predicted = output.acceleration.index({batch.graph.fluid});
  if (predicted.sizes() != batch.target.sizes())
    throw std::invalid_argument("acceleration_mse: the model predicts " +
                                std::to_string(predicted.size(0)) + " fluid rows, the batch has " +
                                std::to_string(batch.target.size(0)) + " targets");
  auto acc = (predicted - batch.target).pow(2).index({batch.mask}).mean();
  const double fraction_weight = settings_.oil_fraction_loss_weight;
  if (!batch.fraction_target.defined() || fraction_weight == 0) return {acc, {{"acc", acc}}};
  const auto change = output.oil_fraction_change.index({batch.graph.fluid});
  if (change.sizes() != batch.fraction_target.sizes())
    throw std::invalid_argument("acceleration_mse: the model predicts " +
                                std::to_string(change.size(0)) +
                                " oil fraction changes, the batch has " +
                                std::to_string(batch.fraction_target.size(0)) + " targets");
  auto frac = (change - batch.fraction_target).pow(2).index({batch.mask}).mean();
  return {acc + fraction_weight * frac, {{"acc", acc}, {"frac", frac}}};
}

}  // namespace gnn
