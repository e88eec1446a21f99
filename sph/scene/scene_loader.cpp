#include "sph/scene/scene_loader.h"

#include <filesystem>
#include <memory>

#include "sph/core/config.h"
#include "sph/forces/non_pressure_force.h"
#include "sph/river/height_map_io.h"
#include "sph/river/river_generator.h"
#include "sph/scene/scene_checks.h"
#include "sph/scene/scene_size.h"
#include "sph/solvers/pressure_solver.h"

namespace sph {

namespace {

// Generates or reads the terrain's height grid. Files are found relative to the scene file.
std::shared_ptr<const Terrain> load_terrain(const TerrainConfig& c, const std::string& file) {
  const std::filesystem::path folder = std::filesystem::path(file).parent_path();
  auto resolve = [&](const std::string& name) { return (folder / name).string(); };
  if (c.source != "river" && c.file.empty())
    throw ConfigError(file, "/terrain/file", "expected a height map file for source " + c.source);
  Terrain t;
  if (c.source == "river") {
    check_river_grid_size(c.river, file, "/terrain/river", physical_memory_bytes());
    t = generate_river(c.river);
  } else if (c.source == "asc") {
    t = read_esri_ascii(resolve(c.file));
  } else {
    if (!(c.cell_size > 0))
      throw ConfigError(file, "/terrain/cell_size", "expected > 0 for a PNG height map");
    if (!(c.z_max > c.z_min))
      throw ConfigError(file, "/terrain/z_max", "expected > /terrain/z_min");
    t = read_height_png(resolve(c.file), c.origin[0], c.origin[1], c.cell_size, c.z_min, c.z_max);
  }
  if (!c.water_mask.empty()) {
    if (c.source == "river")
      throw ConfigError(file, "/terrain/water_mask", "the generated river has its own mask");
    read_water_mask_png(resolve(c.water_mask), t);
  }
  return std::make_shared<const Terrain>(std::move(t));
}

}  // namespace

SceneConfig default_scene() {
  SceneConfig scene;
  for (const auto& solver : pressure_solver_entries())
    for (const auto& section : solver.sections) scene.sections.add(section);
  for (const auto& force : non_pressure_force_entries())
    for (const auto& section : force.sections) scene.sections.add(section);
  return scene;
}

// One pass: read every declared key (each struct checks itself as it is read), make the terrain
// grid, check the scene as a whole.
LoadedScene parse_scene(nlohmann::json j, const std::string& file) {
  LoadedScene out{default_scene(), {}, file};
  JsonReader::read_struct(j, file, "", out.config);
  if (out.config.terrain) out.config.terrain_grid = load_terrain(*out.config.terrain, file);
  check_scene(out.config, file);
  out.resolved = JsonWriter::write_struct(out.config);
  return out;
}

LoadedScene load_scene(const std::string& file, const std::vector<std::string>& overrides) {
  nlohmann::json j = load_json_file(file, "scene file");
  apply_overrides(j, overrides, file);
  return parse_scene(std::move(j), file);
}

std::string scene_reference_markdown() {
  SceneConfig defaults = default_scene();
  DocTable table;
  defaults.describe(table);
  return "| key | unit | default | range | description |\n|---|---|---|---|---|\n" + table.rows();
}

}  // namespace sph
