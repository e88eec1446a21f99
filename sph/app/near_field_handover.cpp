#include "sph/app/near_field_handover.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "common/config_error.h"
#include "common/json_file.h"
#include "common/progress.h"
#include "sph/core/config.h"
#include "sph/io/trajectory_reader.h"
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

// The particles' oil met frame by frame, in identity order (as trajectory.h5 holds it, so that a
// run folder read back meets exactly what the run met): a particle active at one frame and not
// at the next was retired in between (at the outflow or over a terrain edge) and its oil, as its
// retired self holds it, is handed over where it last was in the box; at the end, the oil still
// in the box. The particle count may grow between frames (leaks add particles).
class HandoverTracker {
 public:
  HandoverTracker(const reach::NearFieldWindow& box, Real rest_volume, NearFieldHandover& out)
      : box_(box), rest_volume_(rest_volume), out_(out) {}

  void start(const std::vector<Vec3>& position, const std::vector<std::uint8_t>& active) {
    remember(position, active);
  }
  void frame(double t, const std::vector<Vec3>& position, const std::vector<std::uint8_t>& active,
             const std::vector<Real>& oil_fraction) {
    OilParcelCollector retired(box_, t, true, out_.parcels);
    for (size_t id = 0; id < was_active_.size() && id < active.size(); ++id)
      if (was_active_[id] && !active[id])
        retired.add(last_position_[id], oil_fraction[id], rest_volume_);
    out_.left_m3 += retired.finish();
    remember(position, active);
  }
  void finish(double t, const std::vector<Vec3>& position, const std::vector<std::uint8_t>& active,
              const std::vector<Real>& oil_fraction) {
    OilParcelCollector remaining(box_, t, false, out_.parcels);
    for (size_t id = 0; id < active.size(); ++id)
      if (active[id]) remaining.add(position[id], oil_fraction[id], rest_volume_);
    out_.remaining_m3 = remaining.finish();
  }

 private:
  void remember(const std::vector<Vec3>& position, const std::vector<std::uint8_t>& active) {
    was_active_.resize(active.size(), 0);
    last_position_.resize(active.size());
    for (size_t id = 0; id < active.size(); ++id) {
      was_active_[id] = active[id];
      if (active[id]) last_position_[id] = position[id];
    }
  }

  const reach::NearFieldWindow& box_;
  Real rest_volume_;
  NearFieldHandover& out_;
  std::vector<std::uint8_t> was_active_;
  std::vector<Vec3> last_position_;
};

// A simulation's fluid as a frame of trajectory.h5 holds it.
void frame_of(const Simulation& sim, TrajectoryFrame& frame) {
  const FluidParticles& fluid = sim.fluid();
  frame.time = sim.time();
  frame.position = sim.in_id_order(fluid.position);
  frame.oil_fraction = sim.in_id_order(fluid.oil_fraction);
  frame.active.assign(fluid.size(), 0);
  for (Index s = 0; s < fluid.active; ++s) frame.active[size_t(fluid.id[size_t(s)])] = 1;
}

nlohmann::json box_json(const ReachWindowConfig& w) {
  return {{"centre", w.centre},
          {"length_m", w.length},
          {"width_m", w.width},
          {"heading_deg", w.heading}};
}

// A hand-over of the scene's oil, nothing collected yet.
NearFieldHandover empty_handover(const SceneConfig& c) {
  NearFieldHandover out;
  out.oil_density = double(c.materials.oil.density);
  out.particle_volume_m3 = double(particle_rest_volume(c));
  return out;
}

// What forecast.json's hand-over says of the oil collected, whichever way the near field came.
nlohmann::json oil_summary(const NearFieldHandover& out, const SceneConfig& c, double end_time) {
  return {{"end_time_s", end_time},
          {"parcels", out.parcels.size()},
          {"left_box_m3", out.left_m3},
          {"remaining_in_box_m3", out.remaining_m3},
          {"handed_over_m3", out.left_m3 + out.remaining_m3},
          {"leak_schedule_m3", scheduled_leak_volume(c)},
          {"particle_volume_m3", out.particle_volume_m3},
          {"near_field_oil_density_kg_m3", out.oil_density},
          {"box", box_json(*c.terrain->reach)}};
}

}  // namespace

NearFieldHandover run_near_field_handover(const std::string& scene_file,
                                          const std::vector<std::string>& overrides,
                                          const FarFieldReachRun& far_field,
                                          const std::atomic<bool>* stop, std::ostream* log,
                                          bool terminal) {
  const LoadedScene scene = load_scene(scene_file, overrides);
  const SceneConfig& c = scene.config;
  const reach::NearFieldWindow box = handover_box(c, scene_file, far_field);

  NearFieldHandover out = empty_handover(c);
  Simulation sim(c);
  HandoverTracker tracker(box, particle_rest_volume(c), out);
  TrajectoryFrame frame;
  frame_of(sim, frame);
  tracker.start(frame.position, frame.active);

  const int frames = frame_count(c);
  common::ProgressReporter progress(log ? *log : std::cerr, terminal, frames,
                                    "near field " + c.name);
  FrameLoop loop;
  loop.first = 0;
  loop.last = frames;
  // As spill-sim run steps (scene_runner.cpp), so that its run folder records these very frames.
  loop.frame_dt = shortest_decimal(c.output.frame_dt);
  loop.stop = stop;
  loop.interrupted_note = "nothing written";
  loop.progress = log ? &progress : nullptr;
  run_frames(sim, loop, [&](int, const FrameStats&, double) {
    frame_of(sim, frame);
    tracker.frame(frame.time, frame.position, frame.active, frame.oil_fraction);
  });
  tracker.finish(frame.time, frame.position, frame.active, frame.oil_fraction);
  if (log) progress.finish(std::to_string(out.parcels.size()) + " parcels of oil");

  out.summary = oil_summary(out, c, sim.time());
  out.summary["scene"] = scene_file;
  out.summary["steps"] = sim.steps();
  return out;
}

NearFieldHandover near_field_handover_from_run(const std::string& run_folder,
                                               const FarFieldReachRun& far_field, std::ostream* log,
                                               bool terminal) {
  namespace fs = std::filesystem;
  const fs::path folder(run_folder);
  if (!fs::is_directory(folder))
    throw common::ConfigError(far_field.config_file, far_field.pointer,
                              run_folder +
                                  " is not a folder (a finished spill-sim run or "
                                  "spill-infer predict)");
  for (const char* marker : {"metadata.json", "trajectory.h5"})
    if (!fs::exists(folder / marker))
      throw common::ConfigError(far_field.config_file, far_field.pointer,
                                run_folder + " has no " + marker +
                                    ": not a finished run of spill-sim run or spill-infer predict");
  const std::string metadata_file = (folder / "metadata.json").string();
  const nlohmann::json metadata = common::load_json_file(metadata_file, "run metadata");
  if (!metadata.contains("scene") || !metadata["scene"].is_object())
    throw common::ConfigError(metadata_file, "/scene", "expected the run's resolved scene");
  // The resolved scene names the reach run by its absolute path and the box's heading as used.
  const LoadedScene scene = parse_scene(metadata["scene"], metadata_file + ":/scene");
  const SceneConfig& c = scene.config;
  const reach::NearFieldWindow box = handover_box(c, metadata_file + ":/scene", far_field);

  TrajectoryReader trajectory((folder / "trajectory.h5").string());
  NearFieldHandover out = empty_handover(c);
  HandoverTracker tracker(box, particle_rest_volume(c), out);
  TrajectoryFrame frame;
  trajectory.read(0, frame);
  tracker.start(frame.position, frame.active);
  common::ProgressReporter progress(log ? *log : std::cerr, terminal, trajectory.frames() - 1,
                                    "near field from " + run_folder);
  for (int k = 1; k < trajectory.frames(); ++k) {
    trajectory.read(k, frame);
    tracker.frame(frame.time, frame.position, frame.active, frame.oil_fraction);
    if (!log) continue;
    char when[40];
    std::snprintf(when, sizeof when, "t = %.4g s", frame.time);
    progress.update(k, when);
  }
  tracker.finish(frame.time, frame.position, frame.active, frame.oil_fraction);
  if (log) progress.finish(std::to_string(out.parcels.size()) + " parcels of oil");

  out.summary = oil_summary(out, c, frame.time);
  out.summary["run"] = run_folder;
  out.summary["scene"] = metadata.value("scene_file", "");
  out.summary["frames"] = trajectory.frames();
  if (metadata.contains("predicted_by")) out.summary["predicted_by"] = metadata["predicted_by"];
  if (fs::exists(folder / "stats.json")) {
    const nlohmann::json stats =
        common::load_json_file((folder / "stats.json").string(), "run stats");
    if (stats.contains("summary") && stats["summary"].contains("steps"))
      out.summary["steps"] = stats["summary"]["steps"];
  }
  return out;
}

}  // namespace sph
