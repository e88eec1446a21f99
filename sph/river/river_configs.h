#pragma once
// The settings of a river scene's parts, beside their code in this folder: the terrain and its
// generator (terrain.h, river_generator.h), the flow through the reach (river_flow.h), pipeline
// leaks (leak.h) and the watch points of the spill metrics (spill_metrics.h). Each struct
// declares its parameters once and its own cross-field checks (check()); SceneConfig aggregates
// them.

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include "sph/core/config.h"
#include "sph/core/types.h"

namespace sph {

// The built-in river generator (sph/river/river_generator.h): water flows along +x, its surface is
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

// A near field inside a reach run (`spill-sim reach`): a box at the leak site, turned to run with
// the river, whose terrain, water and inflow come from the run (sph/near_field/reach_terrain.h).
struct ReachWindowConfig {
  std::string run;
  Real time = -1;
  std::vector<double> centre;
  Real length = 0;
  Real width = 0;
  Real heading = -1;
  Real cell_size = Real(0.05);
  Real min_depth = Real(0.01);
  template <class V>
  void describe(V& v) {
    v.field(
        "run", run,
        param("", "Folder of a finished reach run, relative to the scene file's folder").require());
    v.field("time", time,
            param("s", "Output time of the run whose water is used; -1: its last").at_least(-1));
    v.field("centre", centre,
            param("m", "[east, north]: the box's centre in the run's map coordinates").require());
    v.field("length", length, param("m", "Length of the box along the flow").positive().require());
    v.field("width", width, param("m", "Width of the box across the flow").positive().require());
    v.field("heading", heading,
            param("deg",
                  "Compass bearing (clockwise from north) of the box's +x; -1: the direction "
                  "of the reach's mean flow around the centre")
                .at_least(-1)
                .at_most(360));
    v.field("cell_size", cell_size,
            param("m", "Spacing of the terrain grid sampled from the reach").positive());
    v.field("min_depth", min_depth,
            param("m", "Reach water shallower than this is dry land in the near field").positive());
  }
  void check(const std::string& file, const std::string& pointer) const {
    if (centre.size() != 2) throw ConfigError(file, pointer + "/centre", "expected [east, north]");
    if (heading < 0 && heading != -1)
      throw ConfigError(file, pointer + "/heading", "expected -1 or a bearing from 0 to 360");
    if (!(cell_size <= Real(0.1) * std::min(length, width)))
      throw ConfigError(file, pointer + "/cell_size",
                        "expected at most a tenth of the box's length and width");
  }
};

// Terrain of a river scene: from a height map, the built-in generator or a reach run; optionally
// filled with water at rest up to `water_level` where the water mask says so.
struct TerrainConfig {
  std::string source = "river";
  std::string file;
  std::string water_mask;
  Vec3 origin = Vec3::Zero();
  Real cell_size = 0;
  Real z_min = 0;
  Real z_max = 1;
  RiverGeneratorConfig river;
  std::optional<ReachWindowConfig> reach;
  bool fill_water = false;
  Real water_level = 0;
  Vec3 fill_velocity = Vec3::Zero();
  template <class V>
  void describe(V& v) {
    v.field("source", source,
            param("",
                  "river: the built-in generator; asc: an ESRI ASCII grid; png: a grayscale "
                  "height map (8 or 16 bit); reach: a box inside a reach run (the key reach), "
                  "which also sets water_level, fill_velocity and flow/speed")
                .one_of({"river", "asc", "png", "reach"}));
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
    v.field("reach", reach,
            param("",
                  "A box inside a reach run (source reach): x runs with the flow from the box's "
                  "upstream end, y to the left bank, z is the elevation less the water level at "
                  "the inflow"));
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
  bool plug = false;
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
    v.field("plug", plug,
            param("",
                  "Also move the buffer's water at `speed` along x within each step (a plug), "
                  "not only reset its velocity after it, so that friction cannot hold back its "
                  "lowest particles: needed where a layer takes long to enter (deep, slow "
                  "rivers; docs/reach.md)"));
    v.field("reserve_s", reserve_s,
            param("s",
                  "Spare particles for the inflow, in seconds of inflow, before retired ones "
                  "come back; running out stops the run with an error")
                .positive());
  }
  void check(const std::string& file, const std::string& pointer) const {
    if (!(outflow_x > inflow_x))
      throw ConfigError(file, pointer + "/outflow_x", "expected > " + pointer + "/inflow_x");
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

}  // namespace sph
