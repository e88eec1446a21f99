#pragma once
// The settings of the scene's boundary conditions, beside their code (boundary.h, emitter.h):
// walls (boxes, height fields), fluid-boundary friction and emitters. Each struct declares its
// parameters once and its own cross-field checks (check()); SceneConfig aggregates them.

#include <string>
#include <vector>

#include "sph/core/config.h"
#include "sph/core/types.h"

namespace sph {

// Expects max > min on every axis of a box given by its corners at `pointer`.
inline void check_corners(const Vec3& min, const Vec3& max, const std::string& file,
                          const std::string& pointer) {
  for (int k = 0; k < 3; ++k)
    if (!(max[k] > min[k]))
      throw ConfigError(file, pointer + "/max/" + std::to_string(k),
                        "expected max > min on every axis, got min " + std::to_string(min[k]) +
                            " and max " + std::to_string(max[k]));
}

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
  void check(const std::string& file, const std::string& pointer) const {
    check_corners(min, max, file, pointer);
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
  void check(const std::string& file, const std::string& pointer) const {
    if (heights.size() < 2)
      throw ConfigError(file, pointer + "/heights", "expected at least 2 rows");
    for (size_t r = 0; r < heights.size(); ++r)
      if (heights[r].size() != heights[0].size() || heights[r].size() < 2)
        throw ConfigError(file, pointer + "/heights/" + std::to_string(r),
                          "expected rows of equal length >= 2");
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
  void check(const std::string& file, const std::string& pointer) const {
    if (!(stop > start))
      throw ConfigError(
          file, pointer + "/stop",
          "expected stop > start (" + std::to_string(start) + "), got " + std::to_string(stop));
    // A direction too short or too long to normalise in float (1e-30, 1e38) gave NaN positions.
    const double length = direction.cast<double>().norm();
    if (!(length > 1e-6 && length < 1e6))
      throw ConfigError(
          file, pointer + "/direction",
          "expected a direction of length between 1e-6 and 1e6, got " + std::to_string(length));
  }
};

}  // namespace sph
