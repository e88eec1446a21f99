#pragma once
// docs/models.md's L_acc, the objective of GNS and DPI-Nets: the mean squared error of the
// normalised acceleration over the fluid particles that are active in the next frame ("acc"), plus
// oil_fraction_loss_weight times the mean squared error of the normalised change of the oil
// fraction over the same particles ("frac"): every model is a surrogate of both what MTDF-SPH
// moves and how it moves oil between particles. PAGATNet's objective uses it as its L_acc.

#include "common/param_spec.h"
#include "gnn/training/objective.h"

namespace gnn {

// Training config section "acceleration_mse".
struct AccelerationMseSettings {
  double oil_fraction_loss_weight = 1.0;

  template <class V>
  void describe(V& v) {
    v.field("oil_fraction_loss_weight", oil_fraction_loss_weight,
            common::param("", "weight of the oil fraction change's MSE beside the acceleration's")
                .non_negative());
  }
};

class AccelerationMse : public TrainingObjective {
 public:
  static constexpr const char* kSection = "acceleration_mse";
  explicit AccelerationMse(const AccelerationMseSettings& settings = {}) : settings_(settings) {}
  static ObjectiveEntry entry();
  // Its settings' section, which objectives built on it read too.
  static common::ConfigSectionEntry section();
  std::string name() const override { return "acceleration_mse"; }
  ObjectiveValue evaluate(const ModelOutput& output, const TrainingBatch& batch) const override;

 private:
  AccelerationMseSettings settings_;
};

}  // namespace gnn
