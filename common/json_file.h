#pragma once
// Reading a JSON config file with command-line overrides ("/json/pointer=value", value parsed as
// JSON or else taken as a string). Scenes, model configs and training configs all load this way,
// so a missing file, malformed JSON or a bad override is reported alike: a ConfigError naming
// the file (and the pointer).

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace common {

nlohmann::json load_json_file(const std::string& file, const std::string& what);

// Applies "/pointer=value" overrides to `j`; errors name `file` and the pointer.
void apply_overrides(nlohmann::json& j, const std::vector<std::string>& overrides,
                     const std::string& file);

}  // namespace common
