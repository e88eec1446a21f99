#include "train/training_config.h"

#include <cmath>
#include <filesystem>

#include "common/config_visitors.h"
#include "common/json_file.h"
#include "gnn/models/graph_model.h"
#include "train/pushforward.h"

namespace train {

ResolvedConfig load_training_config(const std::string& file,
                                    const std::vector<std::string>& overrides) {
  nlohmann::json j = common::load_json_file(file, "training config");
  common::apply_overrides(j, overrides, file);
  if (!j.is_object()) throw common::ConfigError(file, "", "expected a JSON object");
  nlohmann::json model_overrides = nlohmann::json::object();
  if (j.contains("model")) {
    model_overrides = j["model"];
    if (!model_overrides.is_object())
      throw common::ConfigError(file, "/model", "expected an object of model config keys");
    j.erase("model");
  }
  gnn::move_flat_objective_keys(j, file);
  ResolvedConfig out;
  common::JsonReader::read_struct(j, file, "", out.training);
  check_pushforward(out.training, file);
  out.training_json = common::JsonWriter::write_struct(out.training);
  out.training_json["model"] = model_overrides;
  out.model_file =
      (std::filesystem::path(file).parent_path() / out.training.model_config).lexically_normal();
  out.model_json = common::load_json_file(out.model_file, "model config");
  if (!out.model_json.is_object())
    throw common::ConfigError(out.model_file, "", "expected a JSON object");
  out.model_json.merge_patch(model_overrides);
  // Validates every model key now (unknown key, range), before any output exists.
  out.model_json =
      gnn::make_model(out.model_json, out.model_file + " with " + file + ":/model")->config();
  return out;
}

namespace {

// Removes from `asked` each value that `stored` lacks and that equals its default in `defaults`,
// looking into objects (an objective's section) key by key. An object `stored` lacks is added to
// it empty when `asked` keeps some of its keys, so that they are named one by one
// ("/pagat/distillation_beta", not "/pagat").
void drop_defaults_stored_lacks(const nlohmann::json& defaults, nlohmann::json& stored,
                                nlohmann::json& asked) {
  for (auto it = defaults.begin(); it != defaults.end(); ++it) {
    if (!asked.contains(it.key())) continue;
    nlohmann::json& value = asked[it.key()];
    const bool stored_has = stored.is_object() && stored.contains(it.key());
    if (it->is_object() && value.is_object()) {
      nlohmann::json lacking = nlohmann::json::object();
      drop_defaults_stored_lacks(*it, stored_has ? stored[it.key()] : lacking, value);
      if (stored_has) continue;
      if (value.empty())
        asked.erase(it.key());
      else if (stored.is_object())
        stored[it.key()] = nlohmann::json::object();
    } else if (!stored_has && value == *it) {
      asked.erase(it.key());
    }
  }
}

}  // namespace

std::vector<std::string> keys_that_differ(const nlohmann::json& stored_in,
                                          const nlohmann::json& asked_in) {
  nlohmann::json stored = stored_in, asked = asked_in;
  gnn::move_flat_objective_keys(stored, "the stored training config");
  gnn::move_flat_objective_keys(asked, "the asked training config");
  for (const char* free : {"steps", "description"}) {
    stored.erase(free);
    asked.erase(free);
  }
  drop_defaults_stored_lacks(common::JsonWriter::write_struct(TrainingConfig{}), stored, asked);
  std::vector<std::string> keys;
  for (const auto& op : nlohmann::json::diff(stored, asked))
    keys.push_back(op.at("path").get<std::string>());
  return keys;
}

std::string training_config_reference_markdown() {
  TrainingConfig defaults;
  common::DocTable table;
  defaults.describe(table);
  return "| key | unit | default | range | description |\n|---|---|---|---|---|\n" + table.rows();
}

double learning_rate(const TrainingConfig& c, int64_t step) {
  return (c.lr_max - c.lr_min) * std::pow(0.1, double(step) / double(c.decay_steps)) + c.lr_min;
}

}  // namespace train
