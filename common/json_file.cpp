#include "common/json_file.h"

#include <filesystem>
#include <fstream>

#include "common/config_error.h"

namespace common {

nlohmann::json load_json_file(const std::string& file, const std::string& what) {
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec))
    throw ConfigError(file, "", "is a folder, not the " + what);
  std::ifstream in(file);
  if (!in) throw ConfigError(file, "", "cannot open the " + what);
  try {
    return nlohmann::json::parse(in, nullptr, true, /*ignore_comments=*/true);
  } catch (const nlohmann::json::exception& e) {  // malformed, or a number out of range
    throw ConfigError(file, "", std::string("not valid JSON: ") + e.what());
  }
}

void apply_overrides(nlohmann::json& j, const std::vector<std::string>& overrides,
                     const std::string& file) {
  for (const auto& o : overrides) {
    const auto eq = o.find('=');
    if (eq == std::string::npos || o.empty() || o[0] != '/')
      throw ConfigError(file, o, "a --set override must look like /json/pointer=value");
    const std::string ptr = o.substr(0, eq);
    const std::string text = o.substr(eq + 1);
    nlohmann::json value;
    try {
      value = nlohmann::json::parse(text);
    } catch (const nlohmann::json::out_of_range&) {
      throw ConfigError(file, ptr, "--set " + o + ": the number is out of range");
    } catch (const nlohmann::json::parse_error&) {
      value = text;  // not JSON: take it as a string, e.g. --set /solver=wcsph
    }
    try {
      j[nlohmann::json::json_pointer(ptr)] = value;
    } catch (const nlohmann::json::exception& e) {
      throw ConfigError(file, ptr, std::string("cannot apply --set: ") + e.what());
    }
  }
}

}  // namespace common
