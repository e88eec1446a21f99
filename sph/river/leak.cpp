#include "sph/river/leak.h"

#include <cmath>

#include "sph/core/config.h"

namespace sph {

EmitterConfig leak_emitter(const LeakConfig& leak, const Terrain& t, Real water_level,
                           const std::string& file, size_t index) {
  const std::string ptr = "/leaks/" + std::to_string(index);
  if (leak.x < t.origin_x || leak.x > t.max_x())
    throw ConfigError(file, ptr + "/x", "the pipeline crosses outside the terrain");
  // The wet stretch of the cross-section at x: water cells whose ground lies below the surface.
  Real y_min = 0, y_max = 0;
  bool wet = false;
  for (int iy = 0; iy < t.ny; ++iy) {
    const Real y = t.origin_y + t.cell_size * Real(iy);
    if (!t.is_water(leak.x, y) || t.height_at(leak.x, y) >= water_level) continue;
    y_min = wet ? std::min(y_min, y) : y;
    y_max = wet ? std::max(y_max, y) : y;
    wet = true;
  }
  if (!wet) throw ConfigError(file, ptr + "/x", "the pipeline crosses no water at this x");
  const Real width = y_max - y_min;
  Real y = Real(0.5) * (y_min + y_max);
  if (leak.position == "left_bank") y = y_max - Real(0.2) * width;
  if (leak.position == "right_bank") y = y_min + Real(0.2) * width;
  // -1 and 1 are the bank positions above, a fifth of the width in from either bank.
  if (leak.lateral) y = Real(0.5) * (y_min + y_max) + *leak.lateral * Real(0.3) * width;
  if (!t.is_water(leak.x, y) || t.height_at(leak.x, y) >= water_level)
    throw ConfigError(file, ptr + "/position", "the point under the leak is dry");
  EmitterConfig e;
  e.shape = "disc";
  e.centre = Vec3(leak.x, y, water_level + leak.height);
  e.direction = Vec3(0, 0, -1);
  e.radius = leak.radius;
  e.speed = leak.speed;
  e.rate = leak.rate;
  e.start = leak.start;
  e.stop = leak.start + leak.duration;
  e.material = "oil";
  return e;
}

}  // namespace sph
