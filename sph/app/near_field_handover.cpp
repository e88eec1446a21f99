#include "sph/app/near_field_handover.h"

#include <cmath>
#include <filesystem>
#include <iostream>

#include "common/config_error.h"
#include "common/progress.h"
#include "sph/scene/scene_loader.h"
#include "sph/simulation/frame_loop.h"
#include "sph/simulation/simulation.h"

namespace sph {

namespace {

// The box the scene sits in, as the reach window that turns its points into map coordinates;
// refuses a scene that cannot hand oil over, or that sits in another reach run than the far
// field's.
reach::NearFieldWindow handover_box(const SceneConfig& c, const std::string& scene_file,
                                    const FarFieldReachRun& far_field) {
  if (!c.terrain || !c.terrain->reach)
    throw common::ConfigError(scene_file, "/terrain/source",
                              "a hand-over to the far field needs a near field inside a reach "
                              "run (terrain source \"reach\")");
  if (c.leaks.empty())
    throw common::ConfigError(scene_file, "/leaks", "the near field has no leak to hand over");
  const ReachWindowConfig& w = *c.terrain->reach;
  std::error_code unused;
  if (!std::filesystem::equivalent(w.run, far_field.folder, unused))
    throw common::ConfigError(far_field.config_file, far_field.pointer,
                              scene_file + " sits in the reach run " + w.run +
                                  ", the far field flows on " + far_field.folder +
                                  ": its oil would be handed over on another river; give both "
                                  "the same run");
  reach::NearFieldWindow box;
  box.heading_deg = double(w.heading);
  box.centre_x = w.centre[0];
  box.centre_y = w.centre[1];
  box.length = double(w.length);
  box.width = double(w.width);
  return box;
}

// The oil the scene's leaks were scheduled to release before its end (m^3).
double scheduled_leak_volume(const SceneConfig& c) {
  double leaked = 0;
  for (const auto& leak : c.leaks) {
    const double start = std::min(double(leak.start), double(c.end_time));
    const double end = std::min(double(leak.start + leak.duration), double(c.end_time));
    leaked += double(leak.rate) * std::max(0.0, end - start);
  }
  return leaked;
}

// Where each particle was when last active, so that oil retired since (at the outflow or over a
// terrain edge) is handed over where it left the box.
struct LastActive {
  std::vector<char> active;
  std::vector<Vec3> position;

  void remember(const FluidParticles& fluid) {
    if (active.size() < fluid.position.size()) {
      active.resize(fluid.position.size(), 0);
      position.resize(fluid.position.size());
    }
    for (Index s = 0; s < fluid.active; ++s) {
      const size_t id = size_t(fluid.id[size_t(s)]);
      active[id] = 1;
      position[id] = fluid.position[size_t(s)];
    }
  }
  // The oil of the particles retired since the last call.
  void collect_retired(const FluidParticles& fluid, OilParcelCollector& out) {
    for (Index s = fluid.active; s < fluid.size(); ++s) {
      const size_t id = size_t(fluid.id[size_t(s)]);
      if (id >= active.size() || !active[id]) continue;
      active[id] = 0;
      out.add(position[id], fluid.oil_fraction[size_t(s)], fluid.rest_volume[size_t(s)]);
    }
  }
};

}  // namespace

NearFieldHandover run_near_field_handover(const std::string& scene_file,
                                          const std::vector<std::string>& overrides,
                                          const FarFieldReachRun& far_field,
                                          const std::atomic<bool>* stop, std::ostream* log,
                                          bool terminal) {
  const LoadedScene scene = load_scene(scene_file, overrides);
  const SceneConfig& c = scene.config;
  const reach::NearFieldWindow box = handover_box(c, scene_file, far_field);

  NearFieldHandover out;
  out.oil_density = double(c.materials.oil.density);
  out.particle_volume_m3 = std::pow(double(c.particle_diameter()), 3);
  Simulation sim(c);
  const FluidParticles& fluid = sim.fluid();
  LastActive last;
  last.remember(fluid);

  const int frames = frame_count(c);
  common::ProgressReporter progress(log ? *log : std::cerr, terminal, frames,
                                    "near field " + c.name);
  FrameLoop loop;
  loop.first = 0;
  loop.last = frames;
  loop.frame_dt = double(c.output.frame_dt);
  loop.stop = stop;
  loop.interrupted_note = "nothing written";
  loop.progress = log ? &progress : nullptr;
  run_frames(sim, loop, [&](int, const FrameStats&, double) {
    OilParcelCollector retired(box, sim.time(), true, out.parcels);
    last.collect_retired(fluid, retired);
    out.left_m3 += retired.finish();
    last.remember(fluid);
  });
  // What remains in the box at the end.
  OilParcelCollector remaining(box, sim.time(), false, out.parcels);
  for (Index s = 0; s < fluid.active; ++s)
    remaining.add(fluid.position[size_t(s)], fluid.oil_fraction[size_t(s)],
                  fluid.rest_volume[size_t(s)]);
  out.remaining_m3 = remaining.finish();
  if (log) progress.finish(std::to_string(out.parcels.size()) + " parcels of oil");

  const ReachWindowConfig& w = *c.terrain->reach;
  out.summary = {{"scene", scene_file},
                 {"end_time_s", sim.time()},
                 {"steps", sim.steps()},
                 {"parcels", out.parcels.size()},
                 {"left_box_m3", out.left_m3},
                 {"remaining_in_box_m3", out.remaining_m3},
                 {"handed_over_m3", out.left_m3 + out.remaining_m3},
                 {"leak_schedule_m3", scheduled_leak_volume(c)},
                 {"particle_volume_m3", out.particle_volume_m3},
                 {"near_field_oil_density_kg_m3", out.oil_density},
                 {"box",
                  {{"centre", w.centre},
                   {"length_m", w.length},
                   {"width_m", w.width},
                   {"heading_deg", w.heading}}}};
  return out;
}

}  // namespace sph
