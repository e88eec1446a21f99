#pragma once
// Scene description: what a JSON file in configs/scenes/ holds. Every parameter is declared once
// in a describe() list (name, unit, default, range, description); loading, the resolved copy in
// metadata.json and docs/scene_reference.md all come from those lists. Loading and checking a
// file is scene_loader.h's; a SceneConfig is plain data.

#include <cmath>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "common/config_section.h"
#include "sph/boundary/boundary_configs.h"
#include "sph/core/config.h"
#include "sph/core/physics_context.h"
#include "sph/core/types.h"
#include "sph/river/river_configs.h"
#include "sph/river/terrain.h"
#include "sph/solvers/pressure_solver.h"

namespace sph {

// Volume fractions of the phases; they must sum to 1.
struct FractionsConfig {
  Real water = 1;
  Real oil = 0;
  template <class V>
  void describe(V& v) {
    v.field("water", water, param("", "Volume fraction of water").non_negative().at_most(1));
    v.field("oil", oil, param("", "Volume fraction of oil").non_negative().at_most(1));
  }
  void check(const std::string& file, const std::string& pointer) const {
    if (std::abs(double(water) + double(oil) - 1) > 1e-6)
      throw ConfigError(file, pointer,
                        "expected volume fractions that sum to 1, got water " +
                            std::to_string(water) + " + oil " + std::to_string(oil));
  }
};

struct FluidBlockConfig {
  Vec3 min = Vec3::Zero();
  Vec3 max = Vec3::Zero();
  Vec3 velocity = Vec3::Zero();
  std::string material = "water";
  std::optional<FractionsConfig> fractions;
  // Oil volume fraction of the block's particles (from `fractions`, else from `material`).
  Real oil_fraction() const { return fractions ? fractions->oil : (material == "oil" ? 1 : 0); }
  template <class V>
  void describe(V& v) {
    v.field("min", min, param("m", "Lower corner").require());
    v.field("max", max, param("m", "Upper corner").require());
    v.field("velocity", velocity, param("m/s", "Initial velocity"));
    v.field("material", material, param("", "Phase of the block").one_of({"water", "oil"}));
    v.field("fractions", fractions,
            param("", "Volume fractions of a mixed block (instead of `material`); sum 1"));
  }
  void check(const std::string& file, const std::string& pointer) const {
    check_corners(min, max, file, pointer);
  }
};

struct DomainConfig {
  Vec3 min = Vec3::Zero();
  Vec3 max = Vec3::Zero();
  template <class V>
  void describe(V& v) {
    v.field("min", min, param("m", "Lower corner").require());
    v.field("max", max, param("m", "Upper corner").require());
  }
  void check(const std::string& file, const std::string& pointer) const {
    check_corners(min, max, file, pointer);
  }
};

struct OutputConfig {
  Real frame_dt = Real(0.02);
  template <class V>
  void describe(V& v) {
    v.field("frame_dt", frame_dt,
            param("s", "Simulated time between recorded frames (time steps end exactly on frames)")
                .positive());
  }
};

struct SceneConfig {
  std::string name = "scene";
  std::string description;
  std::string solver = "dfsph";
  std::string kernel = "cubic_spline";
  Real particle_radius = Real(0.025);
  Real support_factor = 4;
  Real end_time = 1;
  Vec3 gravity = Vec3(0, 0, Real(-9.81));
  int reorder_interval = 20;
  TimeStepConfig time_step;
  MaterialsConfig materials;
  Real xsph = 0;
  BoundaryConfig boundary;
  // The settings of every registered pressure solver and force, each declared beside its code
  // (DfsphConfig in solvers/dfsph_solver.h, ...) under its scene key ("dfsph", "mixture", ...).
  // Empty in a default-constructed scene: default_scene() (scene_loader.h) adds them.
  common::ConfigSections sections;
  OutputConfig output;
  std::vector<BoxConfig> boxes;
  std::vector<HeightFieldConfig> height_fields;
  std::vector<FluidBlockConfig> fluid_blocks;
  std::vector<EmitterConfig> emitters;
  std::optional<DomainConfig> domain;
  std::optional<TerrainConfig> terrain;
  std::optional<FlowConfig> flow;
  std::vector<LeakConfig> leaks;
  std::vector<WatchPointConfig> watch_points;
  // The terrain's height grid, loaded or generated when the scene is parsed (not a parameter).
  std::shared_ptr<const Terrain> terrain_grid;

  // The settings section `key` of a solver or force, as the struct its owner declared.
  template <class T>
  const T& settings(const std::string& key) const {
    return sections.get<T>(key);
  }

  Real particle_diameter() const { return 2 * particle_radius; }
  Real support_radius() const { return support_factor * particle_radius; }
  // What solvers and forces are built from (sph/core/physics_context.h).
  PhysicsContext physics() const;

  template <class V>
  void describe(V& v) {
    v.field("name", name, param("", "Short name of the scene"));
    v.field("description", description, param("", "What the scene shows"));
    v.field("solver", solver, param("", "Pressure solver").one_of(pressure_solver_names()));
    v.field("kernel", kernel,
            param("", "Smoothing kernel").one_of({"cubic_spline", "wendland_c2"}));
    v.field("particle_radius", particle_radius,
            param("m", "Fluid particle radius; particles are spaced one diameter apart")
                .positive()
                .at_most(10)
                .require());
    v.field("support_factor", support_factor,
            param("", "Kernel support radius in particle radii").at_least(2).at_most(8));
    v.field("end_time", end_time, param("s", "Simulated time to run").positive().require());
    v.field("gravity", gravity, param("m/s^2", "Gravity; z is up"));
    v.field("reorder_interval", reorder_interval,
            param("steps", "Sort particle arrays by grid cell every this many steps (0: never)")
                .at_least(0));
    v.field("time_step", time_step, param("", "Adaptive time step"));
    v.field("materials", materials, param("", "Fluid phases"));
    v.field("xsph", xsph,
            param("", "XSPH velocity smoothing coefficient").non_negative().at_most(1));
    v.field("boundary", boundary, param("", "Fluid-boundary interaction"));
    sections.describe(v);
    v.field("output", output, param("", "Recording"));
    v.field("boxes", boxes, param("", "Boxes sampled with boundary particles"));
    v.field("height_fields", height_fields,
            param("",
                  "Terrain surfaces sampled with boundary "
                  "particles"));
    v.field("fluid_blocks", fluid_blocks, param("", "Blocks filled with fluid particles"));
    v.field("emitters", emitters, param("", "Sources that release fluid over time"));
    v.field("terrain", terrain,
            param("",
                  "River terrain sampled with boundary particles, optionally filled with "
                  "water"));
    v.field("flow", flow, param("", "Inflow and outflow of a river reach (needs terrain)"));
    v.field("leaks", leaks,
            param("", "Oil leaks from pipelines crossing the river (need terrain)"));
    v.field("watch_points", watch_points,
            param("", "Named places whose oil arrival time spill.json reports"));
    v.field("domain", domain,
            param("",
                  "Simulation domain; particles leaving it stop the run (default: the "
                  "bounding box of boundary and fluid, grown by one support radius)"));
  }
};

// The rest volume of every fluid particle of `scene` (m^3): that of its lattice at the particle
// spacing, so that a block at rest has rest density.
Real particle_rest_volume(const SceneConfig& scene);

// The scene's boundary surfaces as sph/boundary/boundary.h samples them: its height fields, then
// its terrain grid (if any) as one more height field.
std::vector<HeightFieldConfig> boundary_height_fields(const SceneConfig& scene);

}  // namespace sph
