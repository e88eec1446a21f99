#pragma once
// The training objectives' settings as the training config holds them (without LibTorch, so the
// config's readers need not compile it): each objective declares its settings struct beside its
// code and its registry entry names the sections it reads (objective.h, objective_registry.cpp,
// whose header comment says why each objective's settings are a section of their own).

#include <nlohmann/json.hpp>
#include <string>

#include "common/config_section.h"

namespace gnn {

// A section per registered objective's settings, each under its key, at their defaults: what a
// training config holds and reads its values into.
common::ConfigSections objective_sections();

// Training configs made before the objectives declared their settings held the keys flat at the
// top level ("attention_loss_weight": 0.1), and the runs and checkpoints made then store them so.
// Moves each such key of the training config `config` into its section
// ("/pagat/attention_loss_weight"), so those configs read and compare as today's. A key given
// both ways is a ConfigError naming `file` and the flat key.
void move_flat_objective_keys(nlohmann::json& config, const std::string& file);

}  // namespace gnn
