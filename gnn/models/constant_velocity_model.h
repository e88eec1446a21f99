#pragma once
// The constant-velocity floor of docs/models.md: every fluid particle keeps its last velocity (zero
// acceleration), so a rollout advances each position by its last displacement. Every learned
// model must beat it. It has no parameters: it is never trained (spill-train refuses it), only
// checkpointed, rolled out and evaluated like the learned models.
//
// The output is the normalised acceleration that stands for zero physical acceleration:
// (0 - acc_mean) / acc_std with the statistics LearnedSimulator hands over (set_normalisation),
// not a normalised 0, which would be the mean acceleration of the training data (gravity, drag).

#include "common/param_spec.h"
#include "gnn/models/graph_model.h"
#include "gnn/models/model_input_config.h"

namespace gnn {

struct ConstantVelocityConfig {
  std::string model = "constant_velocity";
  // The shared input keys without the type embedding: the graph is still built (the
  // interface is the same for every model), and the noise widens the normalisation as for the
  // learned models.
  ModelInputConfig input;

  template <class V>
  void describe(V& v) {
    using common::param;
    v.field("model", model, param("", "model name").one_of({"constant_velocity"}).require());
    input.describe_without_embedding(v);
  }
};

class ConstantVelocityModel : public GraphModel {
 public:
  explicit ConstantVelocityModel(const ConstantVelocityConfig& config) : config_(config) {}
  // The registry's factory: validates `config` (errors name `file` and the key).
  static std::shared_ptr<GraphModel> from_config(const nlohmann::json& config,
                                                 const std::string& file);
  std::string name() const override { return "constant_velocity"; }
  const ModelInputConfig& input_config() const override { return config_.input; }
  nlohmann::json config() const override;
  void set_normalisation(const Normalisation& normalisation) override;
  double flops(int64_t, int64_t) const override { return 0; }  // it computes nothing

 protected:
  // Throws std::logic_error when no normalisation was set.
  ModelOutput run(const GraphInput& graph, const ForwardOptions& options) override;

 private:
  ConstantVelocityConfig config_;
  torch::Tensor zero_acceleration_;  // [3] -acc_mean / acc_std
};

}  // namespace gnn
