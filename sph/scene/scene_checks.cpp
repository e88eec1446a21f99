#include "sph/scene/scene_checks.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/number_text.h"
#include "sph/boundary/emitter.h"
#include "sph/core/config.h"
#include "sph/river/leak.h"
#include "sph/river/river_flow.h"
#include "sph/scene/scene_size.h"

namespace sph {

namespace {

// Explicit viscosity is stable for dt <= 0.125 d^2 / nu (Simulation limits its steps so); a bound
// below dt_min would silently override dt_min, so it is refused, naming the viscosity at fault.
void check_viscous_time_step(const SceneConfig& s, const std::string& file) {
  bool oil = !s.leaks.empty(), water = s.terrain.has_value() || s.flow.has_value();
  for (const auto& b : s.fluid_blocks) {
    oil = oil || b.oil_fraction() > 0;
    water = water || b.oil_fraction() < 1;
  }
  for (const auto& e : s.emitters) (e.material == "oil" ? oil : water) = true;
  std::string key;
  double nu = 0;
  auto consider = [&](bool used, double value, const std::string& pointer) {
    if (used && value > nu) nu = value, key = pointer;
  };
  consider(water, s.materials.water.viscosity, "/materials/water/viscosity");
  consider(oil, s.materials.oil.viscosity, "/materials/oil/viscosity");
  consider(true, s.boundary.friction, "/boundary/friction");
  if (nu <= 0) return;
  const double d = s.particle_diameter(), limit = 0.125 * d * d / nu;
  if (limit < double(s.time_step.dt_min))
    throw ConfigError(
        file, key,
        "explicit viscosity needs steps of at most 0.125 d^2 / nu = " + common::number_text(limit) +
            " s, below /time_step/dt_min (" + common::number_text(s.time_step.dt_min) +
            " s): lower the viscosity, or dt_min, or use larger particles");
}

std::string format_point(const Vec3& p) {
  return "(" + common::number_text(p[0]) + ", " + common::number_text(p[1]) + ", " +
         common::number_text(p[2]) + ")";
}

// Every part of the geometry must lie inside an explicit /domain: particles outside it cannot be
// found by the neighbour search (a river longer than the domain stopped the run with "point
// outside the domain" and nothing more).
void check_inside_domain(const SceneConfig& s, const std::string& file) {
  const Aabb d{s.domain->min, s.domain->max};
  auto require = [&](const Vec3& lo, const Vec3& hi, const std::string& pointer,
                     const std::string& what) {
    if (d.contains(lo) && d.contains(hi)) return;
    throw ConfigError(file, pointer,
                      what + " spans " + format_point(lo) + " to " + format_point(hi) +
                          ", beyond /domain " + format_point(d.min) + " to " + format_point(d.max) +
                          ": grow /domain or shrink the part");
  };
  for (size_t i = 0; i < s.fluid_blocks.size(); ++i)
    require(s.fluid_blocks[i].min, s.fluid_blocks[i].max, "/fluid_blocks/" + std::to_string(i),
            "the fluid block");
  for (size_t i = 0; i < s.boxes.size(); ++i)
    require(s.boxes[i].min, s.boxes[i].max, "/boxes/" + std::to_string(i), "the box");
  for (size_t i = 0; i < s.height_fields.size(); ++i) {
    const auto& f = s.height_fields[i];
    Real lo = f.heights[0][0], hi = lo;
    for (const auto& row : f.heights)
      for (Real z : row) lo = std::min(lo, z), hi = std::max(hi, z);
    require(Vec3(f.origin[0], f.origin[1], lo),
            Vec3(f.origin[0] + f.cell_size * Real(f.heights[0].size() - 1),
                 f.origin[1] + f.cell_size * Real(f.heights.size() - 1), hi),
            "/height_fields/" + std::to_string(i), "the height field");
  }
  if (s.terrain_grid) {
    const Terrain& t = *s.terrain_grid;
    require(Vec3(t.origin_x, t.origin_y, t.min_height()),
            Vec3(t.max_x(), t.max_y(), std::max(t.max_height(), s.terrain->water_level)),
            "/terrain", "the terrain");
  }
}

// Checks across the scene's parts (each part checks itself as it is read).
void check_consistency(const SceneConfig& s, const std::string& file) {
  if (s.output.frame_dt > s.end_time)
    throw ConfigError(file, "/output/frame_dt", "expected <= /end_time");
  // Frames are counted in an int and the run ends on a frame: refuse what cannot be either.
  const double frames = double(s.end_time) / double(s.output.frame_dt);
  if (frames > 1e7)
    throw ConfigError(file, "/end_time",
                      "expected at most 10,000,000 frames of /output/frame_dt, got " +
                          common::number_text(frames));
  if (std::abs(frames - std::round(frames)) > 1e-3)
    throw ConfigError(file, "/end_time",
                      "expected a whole number of frames of /output/frame_dt (" +
                          common::number_text(s.output.frame_dt) + " s), got " +
                          common::number_text(frames));
  check_viscous_time_step(s, file);
  if (s.flow && !s.terrain) throw ConfigError(file, "/flow", "a river flow needs a /terrain");
  if (!s.leaks.empty() && !s.terrain)
    throw ConfigError(file, "/leaks", "a pipeline leak needs a /terrain to lie over");
  if (s.fluid_blocks.empty() && s.emitters.empty() && s.leaks.empty() &&
      !(s.terrain && s.terrain->fill_water) && !s.flow)
    throw ConfigError(file, "/fluid_blocks",
                      "expected at least one fluid block, emitter or water-filled terrain");
  // A block thinner than a particle diameter holds no particle: it vanished silently, and a
  // scene of such blocks ran with no fluid at all, exit 0.
  const double d = double(s.particle_diameter());
  for (size_t i = 0; i < s.fluid_blocks.size(); ++i)
    for (int k = 0; k < 3; ++k)
      if (std::floor(double(s.fluid_blocks[i].max[k] - s.fluid_blocks[i].min[k]) / d + 1e-4) < 1)
        throw ConfigError(file, "/fluid_blocks/" + std::to_string(i),
                          "thinner than one particle diameter (" + common::number_text(d) +
                              " m, from /particle_radius) along axis " + std::to_string(k) +
                              ": it would hold no particle");
  // A block outside every tank falls away: it ran silently, to a result without that fluid.
  if (!s.boxes.empty() && !s.terrain && s.height_fields.empty())
    for (size_t i = 0; i < s.fluid_blocks.size(); ++i) {
      const auto& b = s.fluid_blocks[i];
      bool held = false;
      for (const auto& box : s.boxes)
        held = held ||
               ((b.min.array() < box.max.array()).all() && (b.max.array() > box.min.array()).all());
      if (!held)
        throw ConfigError(file, "/fluid_blocks/" + std::to_string(i),
                          "spans " + format_point(b.min) + " to " + format_point(b.max) +
                              ", outside every box (/boxes): its fluid would fall away");
    }
  if (s.domain) check_inside_domain(s, file);
}

// The region the scene's geometry spans: /domain if given, else the bounding box of boxes,
// height fields and fluid blocks (Simulation grows it by a support radius).
Aabb geometry_bounds(const SceneConfig& s) {
  if (s.domain) return Aabb{s.domain->min, s.domain->max};
  Aabb b{Vec3::Constant(std::numeric_limits<Real>::max()),
         Vec3::Constant(std::numeric_limits<Real>::lowest())};
  auto grow = [&](const Vec3& p) {
    b.min = b.min.cwiseMin(p);
    b.max = b.max.cwiseMax(p);
  };
  for (const auto& box : s.boxes) grow(box.min), grow(box.max);
  for (const auto& block : s.fluid_blocks) grow(block.min), grow(block.max);
  if (s.terrain_grid) {
    const Terrain& t = *s.terrain_grid;
    grow(Vec3(t.origin_x, t.origin_y, t.min_height()));
    grow(Vec3(t.max_x(), t.max_y(), std::max(t.max_height(), s.terrain->water_level)));
  }
  for (const auto& f : s.height_fields) {
    for (const auto& row : f.heights)
      for (Real z : row) grow(Vec3(f.origin[0], f.origin[1], z));
    grow(Vec3(f.origin[0] + f.cell_size * Real(f.heights[0].size() - 1),
              f.origin[1] + f.cell_size * Real(f.heights.size() - 1), f.origin[2]));
  }
  return b;
}

void check_emitters_inside(const SceneConfig& s, const std::string& file) {
  const Aabb bounds = geometry_bounds(s);
  for (size_t i = 0; i < s.emitters.size(); ++i)
    if (!bounds.contains(s.emitters[i].centre))
      throw ConfigError(file, "/emitters/" + std::to_string(i) + "/centre",
                        "the emitter lies outside the domain spanned by the scene's geometry");
}

// A leak over dry ground or off the terrain, or an outlet whose speed cannot carry its rate,
// is an error naming its entry.
void check_outlets(const SceneConfig& c, const std::string& file) {
  const Real spacing = c.particle_diameter();
  const Real volume = particle_rest_volume(c);
  auto check_outlet = [&](const EmitterConfig& e, const std::string& ptr) {
    try {
      Emitter(e, spacing, volume, PhaseMix{});
    } catch (const EmitterRateError& error) {
      throw ConfigError(file, ptr + "/rate", error.what());
    } catch (const std::invalid_argument& error) {
      throw ConfigError(file, ptr + "/speed", error.what());
    }
  };
  for (size_t i = 0; i < c.emitters.size(); ++i)
    check_outlet(c.emitters[i], "/emitters/" + std::to_string(i));
  for (size_t i = 0; i < c.leaks.size(); ++i)
    check_outlet(leak_emitter(c.leaks[i], *c.terrain_grid, c.terrain->water_level, file, i),
                 "/leaks/" + std::to_string(i));
  // The river's inflow plane must cross water (it was a "flow:" error naming no key, at the
  // start of the run).
  if (c.flow) try {
      RiverFlow::inflow_layer(*c.flow, *c.terrain_grid, c.terrain->water_level, spacing);
    } catch (const std::invalid_argument& error) {
      throw ConfigError(file, "/flow/inflow_x", error.what());
    }
}

}  // namespace

void check_scene(const SceneConfig& scene, const std::string& file) {
  check_consistency(scene, file);
  check_scene_size(scene, file, common::physical_memory_bytes());
  check_outlets(scene, file);
  check_emitters_inside(scene, file);
}

}  // namespace sph
