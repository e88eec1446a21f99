#pragma once
// Scene description: what a JSON file in configs/scenes/ holds. Every parameter is declared once
// in a describe() list (name, unit, default, range, description); loading, the resolved copy in
// metadata.json and docs/scene_reference.md all come from those lists.

#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "common/config_section.h"
#include "sph/core/config.h"
#include "sph/core/types.h"
#include "sph/river/terrain.h"

namespace sph {

std::vector<std::string> pressure_solver_names();  // defined in solver_registry.cpp

struct TimeStepConfig {
  Real cfl = 1;
  Real dt_min = Real(1e-5);
  Real dt_max = Real(0.005);
  template <class V>
  void describe(V& v) {
    v.field("cfl", cfl,
            param("", "CFL number lambda in dt = lambda * 0.4 * diameter / |v|max")
                .positive()
                .at_most(10));
    v.field("dt_min", dt_min, param("s", "Smallest time step").positive());
    v.field("dt_max", dt_max, param("s", "Largest time step").positive());
  }
};

struct FluidMaterialConfig {
  Real density = 1000;
  Real viscosity = Real(0.01);
  template <class V>
  void describe(V& v) {
    v.field("density", density, param("kg/m^3", "Rest density").positive());
    v.field(
        "viscosity", viscosity,
        param("m^2/s", "Kinematic viscosity of the SPH Laplacian viscosity force").non_negative());
  }
};

// The two fluid phases. A particle carries their volume fractions; its rest density and
// viscosity are the fraction-weighted mixture (Ren et al. 2014).
struct MaterialsConfig {
  FluidMaterialConfig water{1000, Real(0.01)};
  // The reference crude oil: 0.94 x water's density, 4 x its viscosity.
  FluidMaterialConfig oil{940, Real(0.04)};
  template <class V>
  void describe(V& v) {
    v.field("water", water, param("", "Water"));
    v.field("oil", oil, param("", "Oil"));
  }
};

// Volume fractions of the phases; they must sum to 1.
struct FractionsConfig {
  Real water = 1;
  Real oil = 0;
  template <class V>
  void describe(V& v) {
    v.field("water", water, param("", "Volume fraction of water").non_negative().at_most(1));
    v.field("oil", oil, param("", "Volume fraction of oil").non_negative().at_most(1));
  }
};

struct BoundaryConfig {
  Real friction = 0;
  template <class V>
  void describe(V& v) {
    v.field("friction", friction,
            param("m^2/s", "Kinematic viscosity between fluid and boundary (0: free slip)")
                .non_negative());
  }
};

struct BoxConfig {
  Vec3 min = Vec3::Zero();
  Vec3 max = Vec3::Zero();
  std::string fluid_side = "inside";
  bool open_top = false;
  template <class V>
  void describe(V& v) {
    v.field("min", min, param("m", "Lower corner").require());
    v.field("max", max, param("m", "Upper corner").require());
    v.field("fluid_side", fluid_side,
            param("", "inside: a tank holding fluid; outside: an obstacle in the fluid")
                .one_of({"inside", "outside"}));
    v.field("open_top", open_top, param("", "Leave out the top face (a tank without a lid)"));
  }
};

// Terrain given as a regular grid of heights z(x, y): heights[iy][ix] at
// (origin.x + ix * cell_size, origin.y + iy * cell_size).
struct HeightFieldConfig {
  Vec3 origin = Vec3::Zero();
  Real cell_size = 0;
  std::vector<std::vector<Real>> heights;
  template <class V>
  void describe(V& v) {
    v.field("origin", origin, param("m", "Position of heights[0][0] (z is ignored)").require());
    v.field("cell_size", cell_size, param("m", "Grid spacing").positive().require());
    v.field("heights", heights,
            param("m", "Rows of heights, heights[iy][ix]; at least 2 x 2").require());
  }
};

// The built-in river generator (sph/river_generator.h): water flows along +x, its surface is
// z = 0, and the reach runs straight, bends, narrows and widens.
struct RiverGeneratorConfig {
  int seed = 1;
  Real length = 8;
  Real width = 2;
  Real depth = Real(0.3);
  Real bank_height = Real(0.25);
  Real bank_slope = 1;
  // Mild enough for a subcritical flow at 1.5 m/s and 0.3 m depth (Froude number 0.87): a
  // narrowing to 0.7 choked it, and the water backed up behind it.
  Real bend_amplitude = Real(0.4);
  Real narrowing = Real(0.85);
  Real widening = Real(1.25);
  Real bed_roughness = Real(0.03);
  Real floodplain = Real(0.2);
  Real cell_size = Real(0.05);
  template <class V>
  void describe(V& v) {
    v.field("seed", seed, param("", "Seed of the bed roughness").at_least(0));
    v.field("length", length, param("m", "Length of the reach along +x").positive());
    v.field("width", width, param("m", "Width of the channel at the water surface").positive());
    v.field("depth", depth, param("m", "Depth of the flat bed below the surface").positive());
    v.field("bank_height", bank_height,
            param("m", "Height of the bank tops above the surface").positive());
    v.field("bank_slope", bank_slope,
            param("", "Horizontal run of the banks per unit rise").positive().at_most(20));
    v.field("bend_amplitude", bend_amplitude,
            param("m", "How far the centreline swings towards +y (the left bank) in the bend"));
    v.field("narrowing", narrowing,
            param("", "Width factor of the narrowing reach").positive().at_most(1));
    v.field("widening", widening,
            param("", "Width factor of the widening reach").at_least(1).at_most(4));
    v.field("bed_roughness", bed_roughness,
            param("m", "Largest height of the seeded bed undulations").non_negative());
    v.field("floodplain", floodplain,
            param("m", "Flat ground beyond each bank top").non_negative());
    v.field("cell_size", cell_size, param("m", "Spacing of the height grid").positive());
  }
};

// Terrain of a river scene: from a height map or the built-in generator; optionally filled with
// water at rest up to `water_level` where the water mask says so.
struct TerrainConfig {
  std::string source = "river";
  std::string file;
  std::string water_mask;
  Vec3 origin = Vec3::Zero();
  Real cell_size = 0;
  Real z_min = 0;
  Real z_max = 1;
  RiverGeneratorConfig river;
  bool fill_water = false;
  Real water_level = 0;
  Vec3 fill_velocity = Vec3::Zero();
  template <class V>
  void describe(V& v) {
    v.field("source", source,
            param("",
                  "river: the built-in generator; asc: an ESRI ASCII grid; png: a grayscale "
                  "height map (8 or 16 bit)")
                .one_of({"river", "asc", "png"}));
    v.field("file", file,
            param("", "Height map file (asc, png), relative to the scene file's folder"));
    v.field("water_mask", water_mask,
            param("",
                  "PNG of the height map's size, nonzero where the river is (asc, png; "
                  "optional: without it every cell below water_level is water)"));
    v.field("origin", origin,
            param("m", "png: position of the south-west (bottom-left) pixel's centre; z unused"));
    v.field("cell_size", cell_size,
            param("m", "png: distance between pixel centres").non_negative());
    v.field("z_min", z_min, param("m", "png: height of gray value 0"));
    v.field("z_max", z_max, param("m", "png: height of the largest gray value"));
    v.field("river", river, param("", "Built-in river generator (source river)"));
    v.field("fill_water", fill_water,
            param("", "Fill the water cells with fluid at rest up to water_level"));
    v.field("fill_velocity", fill_velocity,
            param("m/s",
                  "Initial velocity of the filled water (a river's flow speed shortens "
                  "its warm-up)"));
    v.field("water_level", water_level,
            param("m", "Height of the water surface (the generated river's is 0)"));
  }
};

// Flow through a river reach (needs `terrain`): water enters through the channel's cross-section
// at `inflow_x` at `speed` along +x and particles past `outflow_x` are retired; retired water
// particles are recycled to the inflow (identities stay fixed).
struct FlowConfig {
  Real inflow_x = 0;
  Real outflow_x = 0;
  Real speed = Real(1.5);
  Real buffer = Real(0.1);
  Real reserve_s = Real(1);
  template <class V>
  void describe(V& v) {
    v.field("inflow_x", inflow_x,
            param("m",
                  "Plane where water enters: a layer of particles over the channel's "
                  "cross-section below terrain/water_level")
                .require());
    v.field(
        "outflow_x", outflow_x,
        param("m", "Particles downstream of this plane leave the scene (active = 0)").require());
    v.field("speed", speed, param("m/s", "Inflow speed along +x").positive());
    v.field("buffer", buffer,
            param("m",
                  "Length downstream of inflow_x over which water moves at exactly `speed` "
                  "(the inflow's steady profile), so the flow cannot push back through it")
                .non_negative());
    v.field("reserve_s", reserve_s,
            param("s",
                  "Spare particles for the inflow, in seconds of inflow, before retired ones "
                  "come back; running out stops the run with an error")
                .positive());
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
};

// A source of fluid: a disc or rectangle that releases layers of particles along `direction`
// at `speed`, `rate` cubic metres per second from `start` to `stop` (the reusable element for
// vessel inflows and pipeline leaks).
struct EmitterConfig {
  std::string shape = "disc";
  Vec3 centre = Vec3::Zero();
  Vec3 direction = Vec3(0, 0, -1);
  Real radius = Real(0.05);
  Real width = Real(0.1);
  Real height = Real(0.1);
  Real speed = 1;
  Real rate = 0;
  Real start = 0;
  Real stop = 0;
  std::string material = "water";
  template <class V>
  void describe(V& v) {
    v.field("shape", shape, param("", "Outlet shape").one_of({"disc", "rectangle"}));
    v.field("centre", centre, param("m", "Centre of the outlet").require());
    v.field("direction", direction, param("", "Direction of the outflow (normalised on use)"));
    v.field("radius", radius, param("m", "Disc radius").positive());
    v.field(
        "width", width,
        param("m", "Rectangle side along the horizontal perpendicular of `direction`").positive());
    v.field("height", height, param("m", "Rectangle side along the third axis").positive());
    v.field("speed", speed, param("m/s", "Outflow speed").positive());
    v.field("rate", rate, param("m^3/s", "Volume flow rate").positive().require());
    v.field("start", start, param("s", "When the outflow starts").non_negative());
    v.field("stop", stop, param("s", "When it stops").positive().require());
    v.field("material", material, param("", "Phase released").one_of({"water", "oil"}));
  }
};

// An oil leak from a pipeline crossing the river at `x`: oil pours from the pipe, `height` above
// the water surface, through a round opening of `radius` straight down, at `rate` for `duration`
// from `start` (sph/leak.h turns it into an emitter over the chosen point of the channel).
struct LeakConfig {
  Real x = 0;
  std::string position = "centre";
  std::optional<Real> lateral;
  Real rate = Real(5e-4);
  Real start = 0;
  Real duration = 1;
  Real height = Real(0.1);
  Real radius = Real(0.05);
  Real speed = Real(0.5);
  template <class V>
  void describe(V& v) {
    v.field("x", x, param("m", "Where the pipeline crosses the river, along the flow").require());
    v.field("position", position,
            param("",
                  "Where across the channel the pipe leaks: left_bank (+y, the left looking "
                  "downstream), centre or right_bank; a bank leak is a fifth of the water "
                  "surface's width in from that bank")
                .one_of({"left_bank", "centre", "right_bank"}));
    v.field("lateral", lateral,
            param("",
                  "Instead of `position`, a number from -1 (right_bank) through 0 (centre) to "
                  "1 (left_bank), so that datasets can draw it (--vary)")
                .at_least(-1)
                .at_most(1));
    v.field("rate", rate, param("m^3/s", "Oil leak rate").positive());
    v.field("start", start, param("s", "When the leak starts").non_negative());
    v.field("duration", duration, param("s", "How long it leaks").positive());
    v.field("height", height,
            param("m", "Height of the opening above the water surface").positive());
    v.field("radius", radius, param("m", "Radius of the opening").positive());
    v.field("speed", speed, param("m/s", "Speed of the oil leaving the opening").positive());
  }
};

// A named place on the river (a water intake, a boom site) where the oil's arrival is timed.
struct WatchPointConfig {
  std::string name;
  Real x = 0;
  Real y = 0;
  Real radius = Real(0.2);
  template <class V>
  void describe(V& v) {
    v.field("name", name, param("", "Name reported in spill.json").require());
    v.field("x", x, param("m", "Position along the flow").require());
    v.field("y", y, param("m", "Position across the flow (+y: left bank)").require());
    v.field("radius", radius,
            param("m", "Oil within this distance (seen from above) has arrived").positive());
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

  // Default settings, with a section for every registered solver and force.
  SceneConfig();

  // The settings section `key` of a solver or force, as the struct its owner declared.
  template <class T>
  const T& settings(const std::string& key) const {
    return sections.get<T>(key);
  }

  Real particle_diameter() const { return 2 * particle_radius; }
  Real support_radius() const { return support_factor * particle_radius; }

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

struct LoadedScene {
  SceneConfig config;
  nlohmann::json resolved;  // every parameter, defaults filled in
  std::string file;
};

// Loads a scene file, applying `overrides` ("/json/pointer=value"; value parsed as JSON, or taken
// as a string when it is not JSON) before validation. Throws ConfigError naming file and pointer.
LoadedScene load_scene(const std::string& file, const std::vector<std::string>& overrides = {});

// Validates an in-memory scene (as load_scene does after parsing). `file` names it in errors.
LoadedScene parse_scene(nlohmann::json j, const std::string& file);

// The parameter reference of scene files as a Markdown table.
std::string scene_reference_markdown();

}  // namespace sph
