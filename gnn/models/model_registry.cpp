// The one list of learned models: adding a model is its file pair, its #include and its line
// (with the objective it trains with, gnn/training/objective_registry.cpp).

#include "gnn/models/model_registry.h"

#include <stdexcept>

#include "common/config_error.h"
#include "gnn/models/constant_velocity_model.h"
#include "gnn/models/dpi_model.h"
#include "gnn/models/gns_model.h"
#include "gnn/models/pagat_model.h"

namespace gnn {

std::vector<ModelEntry> model_entries() {
  return {
      // clang-format off
      {"gns",               "acceleration_mse", &GnsModel::from_config},
      {"dpi",               "acceleration_mse", &DpiModel::from_config},
      {"pagat",             "pagat",            &PagatModel::from_config},
      {"constant_velocity", "acceleration_mse", &ConstantVelocityModel::from_config},
      // clang-format on
  };
}

std::vector<std::string> model_names() {
  std::vector<std::string> names;
  for (const auto& e : model_entries()) names.push_back(e.name);
  return names;
}

ModelEntry model_entry(const std::string& name) {
  for (auto& e : model_entries())
    if (e.name == name) return e;
  throw std::invalid_argument("unknown model \"" + name + "\"");
}

std::shared_ptr<GraphModel> make_model(const nlohmann::json& config, const std::string& file) {
  std::string known;
  for (const auto& name : model_names()) known += (known.empty() ? "" : ", ") + name;
  if (!config.is_object()) throw common::ConfigError(file, "", "expected a JSON object");
  if (!config.contains("model") || !config["model"].is_string())
    throw common::ConfigError(file, "/model", "missing the model name (one of: " + known + ")");
  const std::string name = config["model"].get<std::string>();
  for (const auto& e : model_entries())
    if (e.name == name) return e.make(config, file);
  throw common::ConfigError(file, "/model",
                            "unknown model \"" + name + "\" (known: " + known + ")");
}

}  // namespace gnn
