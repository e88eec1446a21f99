#include "common/json_shape.h"

namespace common {

namespace {

const char* describe(JsonKind kind) {
  switch (kind) {
    case JsonKind::kObject:
      return "an object";
    case JsonKind::kArray:
      return "an array";
    case JsonKind::kString:
      return "a string";
    case JsonKind::kNumber:
      return "a number";
    case JsonKind::kInteger:
      return "a whole number";
    case JsonKind::kVector3:
      return "an array of 3 numbers";
  }
  return "";
}

bool has_kind(const nlohmann::json& j, JsonKind kind) {
  switch (kind) {
    case JsonKind::kObject:
      return j.is_object();
    case JsonKind::kArray:
      return j.is_array();
    case JsonKind::kString:
      return j.is_string();
    case JsonKind::kNumber:
      return j.is_number();
    case JsonKind::kInteger:
      return j.is_number_integer();
    case JsonKind::kVector3:
      return j.is_array() && j.size() == 3 && j[0].is_number() && j[1].is_number() &&
             j[2].is_number();
  }
  return false;
}

}  // namespace

const nlohmann::json* optional_json(const nlohmann::json& root, const std::string& pointer,
                                    JsonKind kind, const std::string& file) {
  const nlohmann::json::json_pointer at(pointer);
  // contains() is false for a path through a non-object, so a damaged parent reads as absent
  // here; its own check names it.
  if (!root.contains(at)) return nullptr;
  const nlohmann::json& value = root.at(at);
  if (!has_kind(value, kind))
    throw ConfigError(file, pointer,
                      std::string("expected ") + describe(kind) + ", got " + value.type_name() +
                          " " + value.dump().substr(0, 60));
  return &value;
}

const nlohmann::json& require_json(const nlohmann::json& root, const std::string& pointer,
                                   JsonKind kind, const std::string& file) {
  const nlohmann::json* value = optional_json(root, pointer, kind, file);
  if (!value)
    throw ConfigError(file, pointer, std::string("missing (expected ") + describe(kind) + ")");
  return *value;
}

}  // namespace common
