#include "reach/reach_config.h"

#include <filesystem>

#include "common/json_file.h"

namespace reach {

ReachConfig load_reach_config(const std::string& file, const std::vector<std::string>& overrides) {
  nlohmann::json j = common::load_json_file(file, "reach config");
  common::apply_overrides(j, overrides, file);
  ReachConfig c;
  common::JsonReader::read_struct(j, file, "", c);
  const std::filesystem::path folder = std::filesystem::path(file).parent_path();
  const auto resolve = [&](std::string& name) {
    if (!name.empty() && std::filesystem::path(name).is_relative())
      name = (folder / name).lexically_normal().string();
  };
  resolve(c.terrain.file);
  resolve(c.terrain.manning_file);
  for (auto& in : c.inflows) resolve(in.discharge.file);
  for (auto& out : c.outflows)
    if (out.stage) resolve(out.stage->file);
  return c;
}

std::string reach_reference_markdown() {
  ReachConfig defaults;
  common::DocTable table;
  defaults.describe(table);
  return "| key | unit | default | range | description |\n|---|---|---|---|---|\n" + table.rows();
}

}  // namespace reach
