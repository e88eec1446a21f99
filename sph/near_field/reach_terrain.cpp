#include "sph/near_field/reach_terrain.h"

#include <algorithm>
#include <cmath>

#include "reach/near_field_window.h"
#include "sph/core/config.h"

namespace sph {

ReachNearField near_field_from_reach(const ReachWindowConfig& c, Real inflow_x,
                                     const std::string& scene_file, const std::string& pointer) {
  reach::NearFieldRequest q;
  q.run_dir = c.run;
  q.time = double(c.time);
  q.centre_x = c.centre.at(0);
  q.centre_y = c.centre.at(1);
  q.length = double(c.length);
  q.width = double(c.width);
  q.heading_deg = double(c.heading);
  q.cell_size = double(c.cell_size);
  q.min_depth = double(c.min_depth);
  q.config_file = scene_file;
  q.pointer = pointer;
  const reach::NearFieldWindow w = reach::sample_near_field(q);

  ReachNearField out;
  out.level = w.section_level(double(inflow_x), q.min_depth);
  const double speed = w.section_velocity(double(inflow_x), q.min_depth);
  if (!std::isfinite(out.level) || !(speed > 0))
    throw ConfigError(scene_file, pointer + "/centre",
                      "the reach's water at the inflow section (x = " + std::to_string(inflow_x) +
                          " m in the box) is dry or does not flow into the box (" +
                          std::to_string(speed) + " m/s)");
  out.speed = Real(speed);
  out.heading = w.heading_deg;
  out.time = w.time_s;
  Terrain& t = out.terrain;
  t.origin_x = 0;
  t.origin_y = Real(w.y(0));
  t.cell_size = Real(w.cell_size);
  t.nx = w.nx;
  t.ny = w.ny;
  t.height.resize(w.bed.size());
  t.water.resize(w.bed.size());
  double deepest = 0;
  for (size_t k = 0; k < w.bed.size(); ++k) {
    t.height[k] = Real(w.bed[k] - out.level);
    t.water[k] = w.depth[k] > q.min_depth;
    if (t.water[k]) deepest = std::max(deepest, w.depth[k]);
  }
  // The box's sides run with the flow, along its streamlines, across which no water flows: they
  // are walls. Without them the water where the box cuts through the river (a box narrower than
  // the wet section, or reaching into its shallow edges) ran off the terrain's edge, and the
  // drawdown it set off raced through the box at 6-11 m/s. The outermost row of nodes on each
  // side rises to the deepest water's depth above the level (the height field's boundary fills
  // the step down to the bed), unless the bank there is higher already.
  const Real wall_top = Real(std::max(deepest, 2 * w.cell_size));
  for (int iy : {0, t.ny - 1})
    for (int ix = 0; ix < t.nx; ++ix) {
      Real& h = t.at(ix, iy);
      h = std::max(h, wall_top);
      t.water[size_t(iy) * size_t(t.nx) + size_t(ix)] = 0;
    }
  return out;
}

}  // namespace sph
