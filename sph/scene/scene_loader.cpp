#include "sph/scene/scene_loader.h"

#include <filesystem>
#include <memory>

#include "sph/core/config.h"
#include "sph/forces/non_pressure_force.h"
#include "sph/near_field/reach_terrain.h"
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
  if (c.source == "reach") throw std::logic_error("a reach's terrain comes from use_reach_run");
  if (c.source != "river" && c.file.empty())
    throw ConfigError(file, "/terrain/file", "expected a height map file for source " + c.source);
  Terrain t;
  if (c.source == "river") {
    check_river_grid_size(c.river, file, "/terrain/river", common::physical_memory_bytes());
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

// Terrain source "reach": the box's terrain from the reach run, and the water level, the filled
// water's velocity and the inflow speed with it. Those three may be given only as the reach gives
// them (a resolved scene, reloaded, gives them so); the run's path is made absolute and the
// heading and output time used are written back, so the resolved scene names exactly this box.
// The water level is 0 whatever the reach: z is measured from it.
void use_reach_run(SceneConfig& scene, const nlohmann::json& j, const std::string& file) {
  TerrainConfig& c = *scene.terrain;
  if (!c.reach) throw ConfigError(file, "/terrain/reach", "expected for source reach");
  if (!c.water_mask.empty())
    throw ConfigError(file, "/terrain/water_mask", "the reach's wet cells are the mask");
  ReachWindowConfig& w = *c.reach;
  const std::filesystem::path run = std::filesystem::path(file).parent_path() / w.run;
  w.run = std::filesystem::absolute(run).lexically_normal().string();
  const Real inflow_x = scene.flow ? scene.flow->inflow_x : Real(0.5) * w.length;
  const ReachNearField near = near_field_from_reach(w, inflow_x, file, "/terrain/reach");
  // A value given must be the reach's; the given one is kept, so that a resolved scene reloads
  // to itself (its heading, written to the scene's precision, samples the reach a hair apart).
  const auto from_reach = [&](const char* pointer, Real value) {
    const nlohmann::json::json_pointer p(pointer);
    if (!j.contains(p)) return value;
    const double given = j.at(p).is_number() ? j.at(p).get<double>() : std::nan("");
    if (!(std::abs(given - double(value)) <= 1e-4 * (1 + std::abs(double(value)))))
      throw ConfigError(file, pointer,
                        "comes from the reach run with /terrain/source reach (" +
                            nlohmann::json(shortest_decimal(value)).dump() + "): leave it out");
    return Real(given);
  };
  c.water_level = from_reach("/terrain/water_level", 0);
  c.fill_velocity =
      Vec3(from_reach("/terrain/fill_velocity/0", near.speed),
           from_reach("/terrain/fill_velocity/1", 0), from_reach("/terrain/fill_velocity/2", 0));
  if (scene.flow) {
    FlowConfig& flow = *scene.flow;
    flow.speed = from_reach("/flow/speed", near.speed);
    // A reach's river is deep and slow beside the built-in one's: its inflow needs the plug
    // (river_flow.h), on unless given, and a buffer at least the kernel's support plus a
    // spacing long. Shorter, the water just past the buffer feels the free gap behind the
    // newest layer, and the White River's box at 25 cm spacing (buffer 0.4 m) threw thousands of
    // particles about at up to 13 m/s where 1 m held its 0.64 m/s.
    if (!j.contains(nlohmann::json::json_pointer("/flow/plug"))) flow.plug = true;
    const Real shortest = scene.support_radius() + scene.particle_diameter();
    if (flow.buffer < shortest * Real(1 - 1e-5))
      throw ConfigError(file, "/flow/buffer",
                        "expected at least the kernel's support plus a particle spacing (" +
                            nlohmann::json(shortest_decimal(shortest)).dump() +
                            " m) for a near field in a reach (got " +
                            nlohmann::json(shortest_decimal(flow.buffer)).dump() +
                            " m): a shorter inflow buffer blows a deep, slow river apart");
  }
  w.heading = Real(near.heading);
  w.time = Real(near.time);
  scene.terrain_grid = std::make_shared<const Terrain>(near.terrain);
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
  if (out.config.terrain) {
    if (out.config.terrain->source == "reach")
      use_reach_run(out.config, j, file);
    else
      out.config.terrain_grid = load_terrain(*out.config.terrain, file);
  }
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
