#include "sph/app/near_field_handover.h"

#include <cmath>
#include <filesystem>
#include <iostream>

#include "common/config_error.h"
#include "common/progress.h"
#include "reach/near_field_window.h"
#include "sph/scene/scene_loader.h"
#include "sph/simulation/frame_loop.h"
#include "sph/simulation/simulation.h"

namespace sph {

namespace {

// Traces of oil below this fraction are lumped; parcels of oil above it go one by one.
constexpr Real kOilParticle = Real(0.5);

// Collects the oil of the particles given to it in one frame: one parcel per oil particle, the
// traces summed into one parcel at their oil-weighted mean position and velocity.
struct FrameParcels {
  const reach::NearFieldWindow* box = nullptr;
  double t = 0;
  bool left = true;
  std::vector<NearFieldParcel>* out = nullptr;
  double traces = 0, tx = 0, ty = 0, tu = 0, tv = 0, tarea = 0;
  double total = 0;

  void add(const Vec3& position, const Vec3& velocity, Real oil_fraction, Real rest_volume) {
    const double volume = double(oil_fraction) * double(rest_volume);
    if (!(volume > 0)) return;
    total += volume;
    if (oil_fraction >= kOilParticle) {
      NearFieldParcel p;
      p.t = t;
      p.left = left;
      p.volume = volume;
      p.area = std::cbrt(double(rest_volume) * double(rest_volume));
      to_map(position, velocity, p);
      out->push_back(p);
      return;
    }
    NearFieldParcel p;
    to_map(position, velocity, p);
    traces += volume;
    tx += volume * p.x;
    ty += volume * p.y;
    tu += volume * p.u;
    tv += volume * p.v;
    tarea = std::max(tarea, std::cbrt(double(rest_volume) * double(rest_volume)));
  }
  void to_map(const Vec3& position, const Vec3& velocity, NearFieldParcel& p) const {
    box->to_map(double(position.x()), double(position.y()), p.x, p.y);
    const double a = box->heading_deg * 3.14159265358979323846 / 180;
    const double ex = std::sin(a), ey = std::cos(a);
    p.u = double(velocity.x()) * ex - double(velocity.y()) * ey;
    p.v = double(velocity.x()) * ey + double(velocity.y()) * ex;
  }
  void finish() {
    if (!(traces > 0)) return;
    NearFieldParcel p;
    p.t = t;
    p.left = left;
    p.volume = traces;
    p.x = tx / traces;
    p.y = ty / traces;
    p.u = tu / traces;
    p.v = tv / traces;
    p.area = tarea;
    out->push_back(p);
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

  NearFieldHandover out;
  out.oil_density = double(c.materials.oil.density);
  Simulation sim(c);
  const FluidParticles& fluid = sim.fluid();
  out.particle_volume_m3 = std::pow(double(c.particle_diameter()), 3);
  std::vector<char> was_active(fluid.position.size(), 0);
  std::vector<Vec3> last_position(fluid.position.size()), last_velocity(fluid.position.size());
  const auto remember = [&] {
    if (was_active.size() < fluid.position.size()) {
      was_active.resize(fluid.position.size(), 0);
      last_position.resize(fluid.position.size());
      last_velocity.resize(fluid.position.size());
    }
    for (Index s = 0; s < fluid.active; ++s) {
      const size_t id = size_t(fluid.id[size_t(s)]);
      was_active[id] = 1;
      last_position[id] = fluid.position[size_t(s)];
      last_velocity[id] = fluid.velocity[size_t(s)];
    }
  };
  remember();

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
    // Oil retired since the last frame left the box: at its last position there.
    FrameParcels frame{&box, sim.time(), true, &out.parcels};
    for (Index s = fluid.active; s < fluid.size(); ++s) {
      const size_t id = size_t(fluid.id[size_t(s)]);
      if (id >= was_active.size() || !was_active[id]) continue;
      was_active[id] = 0;
      frame.add(last_position[id], last_velocity[id], fluid.oil_fraction[size_t(s)],
                fluid.rest_volume[size_t(s)]);
    }
    frame.finish();
    out.left_m3 += frame.total;
    remember();
  });
  // What remains in the box at the end.
  FrameParcels remaining{&box, sim.time(), false, &out.parcels};
  for (Index s = 0; s < fluid.active; ++s)
    remaining.add(fluid.position[size_t(s)], fluid.velocity[size_t(s)],
                  fluid.oil_fraction[size_t(s)], fluid.rest_volume[size_t(s)]);
  remaining.finish();
  out.remaining_m3 = remaining.total;
  if (log) progress.finish(std::to_string(out.parcels.size()) + " parcels of oil");

  double leaked = 0;
  for (const auto& leak : c.leaks) {
    const double start = std::min(double(leak.start), double(c.end_time));
    const double end = std::min(double(leak.start + leak.duration), double(c.end_time));
    leaked += double(leak.rate) * std::max(0.0, end - start);
  }
  out.summary = {{"scene", scene_file},
                 {"end_time_s", sim.time()},
                 {"steps", sim.steps()},
                 {"parcels", out.parcels.size()},
                 {"left_box_m3", out.left_m3},
                 {"remaining_in_box_m3", out.remaining_m3},
                 {"handed_over_m3", out.left_m3 + out.remaining_m3},
                 {"leak_schedule_m3", leaked},
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
