#include "sph/app/scene_runner.h"

#include "sph/io/animation.h"
#include "sph/river/spill_metrics.h"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>

#include "common/checked_file.h"
#include "common/image_writer.h"
#include "common/output_folder.h"
#include "common/progress.h"
#include "common/stopwatch.h"
#include "sph/core/config.h"
#include "sph/core/simulation_error.h"
#include "sph/io/run_recorder.h"
#include "sph/io/run_report.h"
#include "sph/io/trajectory_writer.h"

namespace sph {

namespace fs = std::filesystem;

namespace {

void write_json(const fs::path& file, const nlohmann::json& j) {
  common::write_file_atomically(file, j.dump(2) + "\n");
}

nlohmann::json frame_json(const Simulation& sim, const FrameStats& f) {
  return {{"t", sim.time()},
          {"steps", f.steps},
          {"dt_min", f.dt_min},
          {"dt_max", f.dt_max},
          {"density_error_avg", f.density_error_avg},
          {"density_error_max", f.density_error_max},
          {"iterations_density", f.iterations_density},
          {"iterations_divergence", f.iterations_divergence},
          {"kinetic_energy", sim.kinetic_energy()},
          {"active", sim.fluid().active_count()}};
}

}  // namespace

nlohmann::json run_summary(const Simulation& sim, double wall_s, double iterations_density,
                           double iterations_divergence, int threads) {
  const TimeSplit& t = sim.timing();
  const double particle_steps = double(sim.steps()) * double(sim.fluid().active_count());
  nlohmann::json summary = {{"wall_s", wall_s},
                            {"steps", sim.steps()},
                            {"simulated_s", sim.time()},
                            {"fluid_particles", sim.fluid().active_count()},
                            {"boundary_particles", sim.boundary().size()},
                            {"particle_steps_per_s", wall_s > 0 ? particle_steps / wall_s : 0.0},
                            {"iterations_density_avg", iterations_density},
                            {"iterations_divergence_avg", iterations_divergence},
                            {"threads", threads},
                            {"time_split",
                             {{"neighbour_search", t.neighbour_search},
                              {"pressure_solve", t.pressure_solve},
                              {"forces", t.forces},
                              {"other", t.other()}}}};
  for (const auto& [part, seconds] : t.solver_parts) summary["time_split"][part] = seconds;
  // A river's particle budget: entered at the inflow, retired at the outflow, and of those
  // retired, fallen off an edge of the terrain (splashes over a bank); and the oil they carried
  // out of the reach.
  if (const RiverFlow* flow = sim.flow())
    summary["flow"] = {{"emitted", flow->emitted()},
                       {"retired", flow->retired()},
                       {"fallen", flow->fallen()},
                       {"oil_left_m3", flow->oil_left_volume()}};
  return summary;
}

nlohmann::json machine_description(int threads) {
  std::string cpu = "unknown";
  std::ifstream info("/proc/cpuinfo");
  for (std::string line; std::getline(info, line);)
    if (line.rfind("model name", 0) == 0) {
      cpu = line.substr(line.find(':') + 2);
      break;
    }
  return {{"cpu", cpu},
          {"hardware_threads", long(sysconf(_SC_NPROCESSORS_ONLN))},
          {"threads", threads},
#ifdef NDEBUG
          {"build_type", "Release"},
#else
          {"build_type", "Debug"},
#endif
          {"real", sizeof(Real) == 4 ? "float32" : "float64"}};
}

namespace {

// The frame a run records first: 0, or the frame a continued run's state was saved at.
int first_recorded_frame(const Simulation& sim, const LoadedScene& scene, const RunOptions& o) {
  const int frames = frame_count(scene.config);
  const int first = int(std::llround(sim.time() / shortest_decimal(scene.config.output.frame_dt)));
  if (first >= frames)
    throw ConfigError(o.initial_state, "/time",
                      "the state is at t = " + std::to_string(sim.time()) + " s, at or after " +
                          scene.file + "'s /end_time " + std::to_string(scene.config.end_time) +
                          " s: nothing is left to run (raise /end_time with --set)");
  return first;
}

// The frame --save-state-at names (-1 without it), which must lie on the frame grid of the run.
int state_frame(const LoadedScene& scene, const RunOptions& o, int first) {
  if (o.save_state_at < 0) return -1;
  const int frames = frame_count(scene.config);
  const double frame_dt = shortest_decimal(scene.config.output.frame_dt);
  const int frame = int(std::llround(o.save_state_at / frame_dt));
  if (std::abs(double(frame) * frame_dt - o.save_state_at) > 1e-9 * frames || frame < first ||
      frame > frames)
    throw common::InputError(
        "--save-state-at " + std::to_string(o.save_state_at) + ": expected a frame time between " +
        std::to_string(double(first) * frame_dt) + " and " + std::to_string(scene.config.end_time) +
        " s (frames every " + std::to_string(frame_dt) + " s)");
  return frame;
}

}  // namespace

nlohmann::json run_scene(const LoadedScene& scene, const RunOptions& options) {
  common::OutputFolderPolicy policy;
  policy.markers = {"metadata.json", "trajectory.h5", "stats.json"};
  policy.replace = options.force;
  policy.inputs = {scene.file};
  if (!options.initial_state.empty()) policy.inputs.push_back(options.initial_state);
  policy.log = options.log;
  common::OutputFolder output(options.out_dir.string(), policy);
  const fs::path& staging = output.staging();

  // A leak after the end is what a warm-up run (--save-state-at) wants, but is said, never
  // silent: the run releases no oil from it.
  for (size_t i = 0; i < scene.config.leaks.size() && options.log; ++i)
    if (scene.config.leaks[i].start >= scene.config.end_time)
      *options.log << "note: /leaks/" << i << " starts at " << scene.config.leaks[i].start
                   << " s, at or after /end_time (" << scene.config.end_time
                   << " s): this run releases no oil from it\n";
  Simulation sim(scene.config);
  const int frames = frame_count(scene.config);
  const double frame_dt = shortest_decimal(scene.config.output.frame_dt);
  if (!options.initial_state.empty()) sim.load_state(options.initial_state);
  // A continued run records from the frame its state was saved at.
  const int first = first_recorded_frame(sim, scene, options);
  const int save_frame = state_frame(scene, options, first);
  write_json(staging / "metadata.json", run_metadata(sim, scene, frames - first));
  RunRecorder recorder(sim, scene.config, {options.png, options.ply, options.vtk}, staging);

  nlohmann::json frame_list = nlohmann::json::array();
  frame_list.push_back(frame_json(sim, FrameStats{}));
  recorder.record(sim, first);
  if (save_frame == first) sim.save_state((staging / "state.h5").string());
  common::ProgressReporter progress(options.log ? *options.log : std::cerr, options.terminal,
                                    frames, "simulating " + scene.config.name);
  FrameLoop loop;
  loop.first = first;
  loop.last = frames;
  loop.frame_dt = frame_dt;
  loop.stop = options.stop;
  loop.interrupted_note = "nothing written";
  loop.progress = options.log ? &progress : nullptr;
  const FrameLoopTotals totals = run_frames(sim, loop, [&](int frame, const FrameStats& f, double) {
    frame_list.push_back(frame_json(sim, f));
    recorder.record(sim, frame);
    if (frame == save_frame) sim.save_state((staging / "state.h5").string());
  });
  recorder.close_trajectory();
  nlohmann::json summary = run_summary(sim, totals.wall_s, totals.iterations_density,
                                       totals.iterations_divergence, options.threads);
  write_json(staging / "stats.json", {{"frames", frame_list}, {"summary", summary}});
  if (options.png)
    encode_animation(staging, scene.config.terrain_grid ? "river" : "side", first, 1 / frame_dt,
                     options.log);
  recorder.write_metrics();
  write_run_report(staging);
  if (options.log) progress.finish(std::to_string(sim.steps()) + " steps");

  output.commit();
  return summary;
}

nlohmann::json benchmark_scene(const LoadedScene& scene, int threads, std::ostream* log) {
  Simulation sim(scene.config);
  const int frames = frame_count(scene.config);
  common::ProgressReporter progress(log ? *log : std::cerr, false, frames,
                                    "bench " + scene.config.name);
  FrameLoop loop;
  loop.last = frames;
  loop.frame_dt = shortest_decimal(scene.config.output.frame_dt);
  loop.progress = log ? &progress : nullptr;
  // The density error of the states each solver produced, measured the same way for all (the
  // solvers' own figures differ: DFSPH and IISPH report their solve's predicted error, PBF the
  // error at its corrected positions): mean of max(rho/rho0 - 1, 0) over the particles at each
  // frame's end, from the densities of the last neighbour search.
  double state_error = 0;
  const FrameLoopTotals totals = run_frames(sim, loop, [&](int, const FrameStats&, double) {
    const FluidParticles& f = sim.fluid();
    double sum = 0;
    for (Index i = 0; i < f.active_count(); ++i) sum += std::max(0.0, double(f.density[i]) - 1.0);
    state_error += f.active_count() > 0 ? sum / double(f.active_count()) : 0.0;
  });
  const double steps = double(std::max(1L, sim.steps()));
  nlohmann::json j = run_summary(sim, totals.wall_s, totals.iterations_density,
                                 totals.iterations_divergence, threads);
  j["scene"] = scene.config.name;
  j["solver"] = scene.config.solver;
  j["density_error_avg_percent"] = totals.density_error_avg * 100;
  j["state_density_error_percent"] = state_error / double(std::max(1, frames)) * 100;
  j["particle_radius"] = shortest_decimal(scene.config.particle_radius);
  if (scene.config.flow) {
    // The MTDF-SPH paper's river runs: about 100,000 particles for 3,100 frames, projected at
    // this run's particle-steps per second and steps per frame.
    const double steps_per_frame = steps / double(std::max(1, frames));
    const double rate = j["particle_steps_per_s"].get<double>();
    j["paper_workload"] = {{"particles", 100000},
                           {"frames", 3100},
                           {"steps_per_frame", steps_per_frame},
                           {"projected_s", rate > 0 ? 1e5 * steps_per_frame * 3100 / rate : 0.0}};
  }
  return j;
}

}  // namespace sph
