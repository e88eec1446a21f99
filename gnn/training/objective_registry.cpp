// The one list of training objectives: adding an objective is its file pair (its settings struct
// with describe(), the objective, its entry), its #include and its line; a model trains with it
// when its line in gnn/models/model_registry.cpp names it.
//
// Where the settings live in the training config: a section per objective, under the key its
// entry registers ({"acceleration_mse": {"oil_fraction_loss_weight": 1}, "pagat":
// {"attention_loss_weight": 0.1, ...}}), as the scene holds a section per pressure solver. Why
// not the flat top-level keys the configs used before: the training config then holds the
// objectives' settings without knowing their types (common::ConfigSections, as sph::SceneConfig
// does), so a new objective adds no line to it; two objectives can name a setting alike without
// clashing; and the config and its reference say which objective each setting belongs to. The
// price is the eight keys that configs, runs (RUN/config.json) and checkpoints made before held
// flat: kFlatKeys below reads each of them into its section wherever a training config is read
// (a config file and its --set overrides, a stored config on --resume and in keys_that_differ),
// so those runs resume and compare unchanged. The shipped configs use the sections; a new
// objective's keys are never read flat.

#include <stdexcept>
#include <utility>

#include "common/config_error.h"
#include "gnn/models/model_registry.h"
#include "gnn/training/acceleration_mse.h"
#include "gnn/training/objective.h"
#include "gnn/training/pagat_objective.h"

namespace gnn {

std::vector<ObjectiveEntry> objective_entries() {
  return {
      // clang-format off
      AccelerationMse::entry(),
      PagatObjective::entry(),
      // clang-format on
  };
}

namespace {

// The keys training configs held flat before the objectives had sections, each with its section.
// Closed: no key joins it.
const std::vector<std::pair<std::string, std::string>> kFlatKeys = {
    {"oil_fraction_loss_weight", "acceleration_mse"},
    {"acceleration_loss_weight", "pagat"},
    {"attention_loss_weight", "pagat"},
    {"distillation_loss_weight", "pagat"},
    {"distillation_beta", "pagat"},
    {"generator_strength", "pagat"},
    {"generator_until", "pagat"},
    {"distillation_stride", "pagat"},
};

}  // namespace

common::ConfigSections objective_sections() {
  common::ConfigSections sections;
  for (const auto& objective : objective_entries())
    for (const auto& section : objective.sections) sections.add(section);
  return sections;
}

void move_flat_objective_keys(nlohmann::json& config, const std::string& file) {
  if (!config.is_object()) return;  // the reader names what it expected
  for (const auto& [key, section] : kFlatKeys) {
    if (!config.contains(key)) continue;
    // A section that is not an object stays for the reader to refuse.
    if (config.contains(section) && !config[section].is_object()) continue;
    nlohmann::json& into = config[section];
    if (into.contains(key))
      throw common::ConfigError(
          file, "/" + key,
          "also given as /" + section + "/" + key + ": give it once, as /" + section + "/" + key);
    into[key] = config[key];
    config.erase(key);
  }
}

ObjectiveEntry objective_entry(const std::string& name) {
  for (auto& e : objective_entries())
    if (e.name == name) return e;
  throw std::invalid_argument("unknown training objective \"" + name + "\"");
}

ObjectiveEntry model_objective(const std::string& model_name) {
  return objective_entry(model_entry(model_name).objective);
}

std::unique_ptr<TrainingObjective> make_objective(GraphModel& model,
                                                  const ObjectiveInputs& inputs) {
  const ObjectiveEntry objective = model_objective(model.name());
  if (inputs.teacher && !objective.distils) {
    std::string distilling;
    for (const auto& e : objective_entries())
      if (e.distils) distilling += (distilling.empty() ? "" : ", ") + e.name;
    throw std::invalid_argument("distillation needs a student whose objective distils (" +
                                distilling + "), not " + model.name() + " (trained with " +
                                objective.name + ")");
  }
  return objective.make(model, inputs);
}

}  // namespace gnn
