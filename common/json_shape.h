#pragma once
// Shape checks of a JSON document we wrote ourselves and read back (a dataset's metadata.json, a
// trajectory part file): a damaged or hand-edited file is a ConfigError naming the file and the
// key, not a raw nlohmann type error naming neither.

#include <nlohmann/json.hpp>
#include <string>

#include "common/config_error.h"

namespace common {

enum class JsonKind { kObject, kArray, kString, kNumber, kInteger, kVector3 };

// The value at `pointer` in `root`, which must exist and be of `kind`; else a ConfigError.
const nlohmann::json& require_json(const nlohmann::json& root, const std::string& pointer,
                                   JsonKind kind, const std::string& file);

// The same for an optional key: nullptr when it is absent.
const nlohmann::json* optional_json(const nlohmann::json& root, const std::string& pointer,
                                    JsonKind kind, const std::string& file);

}  // namespace common
