#pragma once
// How a learned model is registered (one line in model_registry.cpp): everything about it that
// the rest of the pipeline needs, so nothing else tests a model's name.

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "gnn/models/graph_model.h"

namespace gnn {

struct ModelEntry {
  std::string name;  // the config's "model" value, and the built model's name()
  // The training objective it is trained with (an ObjectiveEntry's name, objective_registry.cpp).
  std::string objective;
  // Validates `config` (errors name `file` and the key) and builds the model.
  std::shared_ptr<GraphModel> (*make)(const nlohmann::json& config, const std::string& file);
};

// Every registered model, in the registry's order.
std::vector<ModelEntry> model_entries();
// The entry of `name`. Throws std::invalid_argument for an unknown name.
ModelEntry model_entry(const std::string& name);

}  // namespace gnn
