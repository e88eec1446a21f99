#include "sph/scene/scene_size.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

#include "sph/core/config.h"
#include "sph/river/river_generator.h"

namespace sph {

namespace {

// Bytes per terrain grid cell: height and water mask, the boundary sampler's copy of the height.
constexpr double kBytesPerGridCell = 12;
// Bytes per cell of the neighbour search: two grids (fluid, boundary), each with a start offset
// and a fill counter per cell. Measured 15.4 B from the resident size of river_case1 with
// /domain/max/0 = 8400 (7e7 cells); the fuzzer found that the 4 B assumed before let it through
// a 1 GB limit to a std::bad_alloc.
constexpr double kBytesPerNeighbourCell = 16;
// Particle indices are 32-bit.
constexpr double kMaxParticles = double(std::numeric_limits<Index>::max());

std::string amount(double v) {
  std::ostringstream s;
  s.precision(3);
  s << v;
  return s.str();
}

std::string bytes(double b) {
  return amount(b / double(1ull << 30)) + " GiB";
}

// Points of a lattice of `spacing` over `length`, ends included, in double so nothing overflows.
double points_along(double length, double spacing) {
  return std::floor(std::max(0.0, length) / spacing) + 1;
}

}  // namespace

void check_river_grid_size(const RiverGeneratorConfig& r, const std::string& file,
                           const std::string& pointer, double memory_bytes) {
  const auto across = river_half_span_terms(r);
  double half_span = 0;
  for (const auto& a : across) half_span += double(a.second);
  auto fits = [&](double cell, double& nx, double& ny, double& need) {
    nx = std::ceil(double(r.length) / cell) + 1;
    ny = 2 * std::ceil(half_span / cell) + 1;
    need = nx * ny * kBytesPerGridCell;
    return nx < 2e9 && ny < 2e9 && need <= memory_bytes;
  };
  const double cell = double(r.cell_size);
  double nx = 0, ny = 0, need = 0;
  if (fits(cell, nx, ny, need)) return;
  // Blame the cell size when the reach would fit at the default one, else its longest extent.
  double unused[3];
  std::string key = "length";
  if (fits(std::max(cell, double(RiverGeneratorConfig{}.cell_size)), unused[0], unused[1],
           unused[2]))
    key = "cell_size";
  else if (ny > nx)
    key = std::max_element(across.begin(), across.end(), [](const auto& a, const auto& b) {
            return a.second < b.second;
          })->first;
  throw ConfigError(file, pointer + "/" + key,
                    "the generated terrain would be " + amount(nx) + " x " + amount(ny) +
                        " cells of " + amount(cell) + " m (" + amount(double(r.length)) + " m x " +
                        amount(2 * half_span) + " m), " + bytes(need) + "; this process may use " +
                        bytes(memory_bytes) + " of memory. Use " +
                        (key == "cell_size" ? "a larger cell_size"
                                            : "a smaller " + key + " or a larger cell_size"));
}

std::vector<ScenePart> estimate_particles(const SceneConfig& s) {
  const double d = double(s.particle_diameter());
  const double particle_volume = d * d * d;
  std::vector<ScenePart> parts;
  for (size_t i = 0; i < s.boxes.size(); ++i) {
    const Vec3 e = s.boxes[i].max - s.boxes[i].min;
    double n = 1;
    for (int k = 0; k < 3; ++k) n *= points_along(double(e[k]), d);
    double inner = 1;
    for (int k = 0; k < 3; ++k) inner *= std::max(0.0, points_along(double(e[k]), d) - 2);
    parts.push_back({"/boxes/" + std::to_string(i), n - inner});  // the lattice's surface
  }
  for (size_t i = 0; i < s.height_fields.size(); ++i) {
    const auto& f = s.height_fields[i];
    const double lx = double(f.cell_size) * double(f.heights[0].size() - 1);
    const double ly = double(f.cell_size) * double(f.heights.size() - 1);
    parts.push_back(
        {"/height_fields/" + std::to_string(i), points_along(lx, d) * points_along(ly, d)});
  }
  for (size_t i = 0; i < s.fluid_blocks.size(); ++i) {
    const Vec3 e = s.fluid_blocks[i].max - s.fluid_blocks[i].min;
    double n = 1;
    for (int k = 0; k < 3; ++k) n *= points_along(double(e[k]), d);
    parts.push_back({"/fluid_blocks/" + std::to_string(i), n});
  }
  if (s.terrain_grid) {
    const Terrain& t = *s.terrain_grid;
    const double cell = double(t.cell_size);
    parts.push_back(
        {"/terrain", points_along(cell * (t.nx - 1), d) * points_along(cell * (t.ny - 1), d)});
    const double level = double(s.terrain->water_level);
    if (s.terrain->fill_water) {
      double water_volume = 0;
      for (int iy = 0; iy < t.ny; ++iy)
        for (int ix = 0; ix < t.nx; ++ix)
          if (t.water.empty() || t.water[size_t(iy) * size_t(t.nx) + size_t(ix)])
            water_volume += std::max(0.0, level - double(t.at(ix, iy))) * cell * cell;
      parts.push_back({"/terrain/fill_water", water_volume / particle_volume});
    }
    if (s.flow) {
      // The inflow's reserve: its cross-section in layers of one spacing, reserve_s of them.
      double section = 0;
      for (int iy = 0; iy < t.ny; ++iy)
        section += std::max(0.0, level - double(t.height_at(s.flow->inflow_x,
                                                            t.origin_y + t.cell_size * Real(iy)))) *
                   cell;
      const double layers = std::max(2.0, double(s.flow->reserve_s) * double(s.flow->speed) / d);
      parts.push_back({"/flow/reserve_s", layers * section / (d * d)});
    }
  }
  // An outlet: its layer (named by its size) and every particle it will release (its rate).
  auto outlet = [&](const std::string& pointer, const std::string& size_key, double area,
                    double released) {
    parts.push_back({pointer + "/" + size_key, area / (d * d)});
    parts.push_back({pointer + "/rate", released / particle_volume});
  };
  for (size_t i = 0; i < s.emitters.size(); ++i) {
    const auto& e = s.emitters[i];
    const bool disc = e.shape == "disc";
    outlet("/emitters/" + std::to_string(i), disc ? "radius" : "width",
           disc ? M_PI * double(e.radius) * double(e.radius) : double(e.width) * double(e.height),
           double(e.rate) * (double(e.stop) - double(e.start)));
  }
  for (size_t i = 0; i < s.leaks.size(); ++i) {
    const auto& l = s.leaks[i];
    outlet("/leaks/" + std::to_string(i), "radius", M_PI * double(l.radius) * double(l.radius),
           double(l.rate) * double(l.duration));
  }
  return parts;
}

void check_scene_size(const SceneConfig& s, const std::string& file, double memory_bytes) {
  const std::vector<ScenePart> parts = estimate_particles(s);
  double total = 0;
  const ScenePart* largest = nullptr;
  for (const auto& p : parts) {
    total += p.particles;
    if (!largest || p.particles > largest->particles) largest = &p;
  }
  const double need = total * kBytesPerParticle;
  if (largest && (!(need <= memory_bytes) || !(total <= kMaxParticles)))
    throw ConfigError(file, largest->pointer,
                      "the scene would need about " + amount(total) + " particles at " +
                          "/particle_radius " + amount(double(s.particle_radius)) + " m (" +
                          amount(largest->particles) + " here), " + bytes(need) + " at " +
                          amount(kBytesPerParticle) + " bytes each; this process may use " +
                          bytes(memory_bytes) + " of memory" +
                          (total <= kMaxParticles ? "" : " and particles are counted in 32 bits") +
                          ". Make this part smaller or /particle_radius larger");
  if (s.domain) {
    double cells = 1;
    const Vec3 e = s.domain->max - s.domain->min;
    for (int k = 0; k < 3; ++k) cells *= std::ceil(double(e[k]) / double(s.support_radius()));
    const double grid_bytes = cells * kBytesPerNeighbourCell;
    if (!(grid_bytes + need <= memory_bytes) || !(cells <= 2147483648.0))
      throw ConfigError(file, "/domain",
                        "the neighbour grid over the domain would have " + amount(cells) +
                            " cells of one support radius (" + amount(double(s.support_radius())) +
                            " m), " + bytes(grid_bytes) + " beside the particles' " + bytes(need) +
                            "; this process may use " + bytes(memory_bytes) +
                            " of memory and at most 2.1e9 cells fit. Make /domain smaller");
  }
}

}  // namespace sph
