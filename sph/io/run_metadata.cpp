#include "sph/io/run_metadata.h"

#include <algorithm>
#include <cmath>

#include "sph/core/config.h"

namespace sph {

namespace {
nlohmann::json vec_json(const Vec3& v) {
  return {double(v[0]), double(v[1]), double(v[2])};
}
}  // namespace

nlohmann::json run_metadata(const Simulation& sim, const LoadedScene& scene, int frames) {
  const SceneConfig& s = scene.config;
  const Aabb& d = sim.domain();
  const double stride =
      std::max(1.0, std::round(shortest_decimal(s.output.frame_dt) / double(s.time_step.dt_max)));
  return {{"dim", 3},
          {"frame_dt", shortest_decimal(s.output.frame_dt)},
          {"dt", shortest_decimal(s.output.frame_dt)},
          {"frame_stride", long(stride)},
          {"frame_stride_note",
           "solver steps per frame at dt_max; the adaptive step may take more, see stats.json"},
          {"sequence_length", frames + 1},
          {"bounds",
           {{shortest_decimal(d.min[0]), shortest_decimal(d.max[0])},
            {shortest_decimal(d.min[1]), shortest_decimal(d.max[1])},
            {shortest_decimal(d.min[2]), shortest_decimal(d.max[2])}}},
          {"particle_radius", shortest_decimal(s.particle_radius)},
          {"support_radius", shortest_decimal(s.support_radius())},
          {"default_connectivity_radius", shortest_decimal(s.support_radius())},
          {"gravity", vec_json(s.gravity)},
          {"solver", s.solver},
          {"kernel", s.kernel},
          {"fluid_particles", sim.fluid().size()},
          {"boundary_particles", sim.boundary().size()},
          {"particle_types", {{"water", 0}, {"oil", 1}, {"boundary", 2}}},
          {"scene_file", scene.file},
          {"scene", scene.resolved}};
}

}  // namespace sph
