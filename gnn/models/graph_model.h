#pragma once
// The interface every learned simulator implements (GNS here; DPI-Nets and PAGATNet plug in the
// same way): one graph in, the normalised acceleration of every node out. The factory builds a
// model from its JSON config by the config's "model" name, validating every key.

#include <torch/torch.h>

#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "gnn/data/dataset.h"
#include "gnn/graph/graph_input.h"

namespace gnn {

class GraphModel : public torch::nn::Module {
 public:
  // Normalised acceleration [n, 3] of every node (only fluid rows are used).
  virtual torch::Tensor forward(const GraphInput& graph) = 0;
  virtual std::string name() const = 0;
  // Input settings shared by all models, from the model's config.
  virtual double radius() const = 0;     // connectivity radius, m
  virtual double noise_std() const = 0;  // training noise on velocities, m per frame
  // The resolved config (defaults filled in), stored in checkpoints.
  virtual nlohmann::json config() const = 0;
};

// Builds the model named by config["model"]; `file` names the config in errors (ConfigError
// with the key path for unknown keys, wrong types and out-of-range values).
std::shared_ptr<GraphModel> make_model(const nlohmann::json& config, const std::string& file);

}  // namespace gnn
