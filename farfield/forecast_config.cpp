#include "farfield/forecast_config.h"

#include <filesystem>

#include "common/json_file.h"

namespace farfield {

ForecastConfig load_forecast_config(const std::string& file,
                                    const std::vector<std::string>& overrides) {
  nlohmann::json j = common::load_json_file(file, "forecast config");
  // An oil given by name alone is the object with only its name (before the overrides, which
  // may set its other keys, and after, which may name it alone).
  const auto oil_as_object = [&j] {
    if (j.is_object() && j.contains("oil") && j["oil"].is_string())
      j["oil"] = nlohmann::json{{"name", j["oil"]}};
  };
  oil_as_object();
  common::apply_overrides(j, overrides, file);
  oil_as_object();
  ForecastConfig c;
  common::JsonReader::read_struct(j, file, "", c);
  const std::filesystem::path folder = std::filesystem::path(file).parent_path();
  const auto resolve = [&](std::string& name) {
    if (!name.empty() && std::filesystem::path(name).is_relative())
      name = (folder / name).lexically_normal().string();
  };
  resolve(c.flow.reach_run);
  for (auto& r : c.releases) resolve(r.rate.file);
  resolve(c.environment.water_temperature.file);
  resolve(c.environment.wind_speed.file);
  resolve(c.environment.wind_from.file);
  if (c.environment.wave_height) resolve(c.environment.wave_height->file);
  if (c.oil.name.find('/') != std::string::npos) resolve(c.oil.name);
  if (c.near_field) {
    resolve(c.near_field->scene);
    resolve(c.near_field->run);
  }
  if (c.ensemble)
    for (auto& oil : c.ensemble->oils)
      if (oil.find('/') != std::string::npos) resolve(oil);
  return c;
}

std::string forecast_reference_markdown() {
  ForecastConfig defaults;
  common::DocTable table;
  defaults.describe(table);
  return "| key | unit | default | range | description |\n|---|---|---|---|---|\n" + table.rows();
}

}  // namespace farfield
