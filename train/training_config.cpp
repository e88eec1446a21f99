#include "train/training_config.h"

#include <cmath>
#include <filesystem>

#include "common/config_visitors.h"
#include "common/json_file.h"
#include "gnn/models/graph_model.h"

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
  ResolvedConfig out;
  common::JsonReader::read_struct(j, file, "", out.training);
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

std::vector<std::string> keys_that_differ(const nlohmann::json& stored_in,
                                          const nlohmann::json& asked_in) {
  nlohmann::json stored = stored_in, asked = asked_in;
  stored.erase("steps");
  asked.erase("steps");
  const nlohmann::json defaults = common::JsonWriter::write_struct(TrainingConfig{});
  for (auto it = defaults.begin(); it != defaults.end(); ++it)
    if (!stored.contains(it.key()) && asked.contains(it.key()) && asked[it.key()] == it.value())
      asked.erase(it.key());
  std::vector<std::string> keys;
  for (const auto& op : nlohmann::json::diff(stored, asked))
    keys.push_back(op.at("path").get<std::string>());
  return keys;
}

double learning_rate(const TrainingConfig& c, int64_t step) {
  return (c.lr_max - c.lr_min) * std::pow(0.1, double(step) / double(c.decay_steps)) + c.lr_min;
}

}  // namespace train
