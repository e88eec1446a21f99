#pragma once
// A small config of every registered model, for the tests that cover all of them by enumerating
// the registry (gnn::model_names()). A model registered without a config here fails those tests
// with this message until one is added, rather than going untested.
#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

namespace small_models {

inline nlohmann::json config(const std::string& model) {
  static const std::map<std::string, nlohmann::json> configs = {
      {"gns", {{"model", "gns"}, {"latent", 16}, {"layers", 2}, {"mlp_hidden_layers", 1}}},
      {"dpi",
       {{"model", "dpi"},
        {"particle_width", 24},
        {"relation_width", 32},
        {"effect_width", 16},
        {"propagation_steps", 2},
        {"encoder_hidden_layers", 1}}},
      {"pagat",
       {{"model", "pagat"},
        {"latent", 16},
        {"blocks", 2},
        {"heads", 2},
        {"physics_width", 8},
        {"radius", 0.1}}},
      {"constant_velocity", {{"model", "constant_velocity"}}},
  };
  const auto it = configs.find(model);
  if (it == configs.end())
    throw std::logic_error("model \"" + model +
                           "\" is registered, but tests/gnn/small_models.h has no small config "
                           "for it: add one, so that the tests over every model cover it");
  return it->second;
}

}  // namespace small_models
