#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <numeric>
#include <sstream>

#include "common/checked_file.h"
#include "common/config_error.h"
#include "common/output_folder.h"
#include "common/progress.h"
#include "common/stop_signals.h"
#include "gnn/eval/scene_rollout.h"
#include "gnn/eval/spill_measures.h"
#include "gnn/runtime/runtime.h"
#include "gnn/training/checkpoint.h"
#include "infer/commands.h"
#include "sph/core/config.h"
#include "sph/io/animation.h"
#include "sph/io/run_metadata.h"
#include "sph/io/run_recorder.h"
#include "sph/io/run_report.h"
#include "sph/scene/scene_loader.h"
#include "sph/simulation/density_relaxation.h"
#include "sph/simulation/frame_loop.h"

namespace infer {
namespace fs = std::filesystem;

namespace {

std::string text(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// A model runs only on scenes like its data: the same frame interval, particle size and graph
// radius (its features are in those units), and fluid phases it has seen.
void check_scene_fits(const nlohmann::json& data, const sph::LoadedScene& scene,
                      const std::string& checkpoint) {
  const sph::SceneConfig& s = scene.config;
  const auto require_equal = [&](const char* what, const char* pointer, double trained,
                                 double given) {
    if (std::abs(trained - given) > 1e-6 * std::abs(trained))
      throw common::ConfigError(scene.file, pointer,
                                std::string(what) + " is " + text(given) + ", but " + checkpoint +
                                    " was trained on data with " + text(trained) +
                                    " (set it with --set, or use a model trained for it)");
  };
  require_equal("the frame interval (s)", "/output/frame_dt", data.value("frame_dt", 0.0),
                sph::shortest_decimal(s.output.frame_dt));
  require_equal("the particle radius (m)", "/particle_radius", data.value("particle_radius", 0.0),
                sph::shortest_decimal(s.particle_radius));
  require_equal("the connectivity radius (the support radius, m)", "/particle_radius",
                data.value("connectivity_radius", 0.0), sph::shortest_decimal(s.support_radius()));
  // The phases the scene's fluid starts as or is released as.
  bool water = s.terrain && s.terrain->fill_water, oil = false;
  for (const auto& b : s.fluid_blocks) (b.oil_fraction() >= 0.5 ? oil : water) = true;
  for (const auto& e : s.emitters) (e.material == "oil" ? oil : water) = true;
  water = water || bool(s.flow);
  oil = oil || !s.leaks.empty();
  const nlohmann::json types = data.value("particle_types", nlohmann::json::object());
  const auto knows = [&](const char* phase) { return types.contains(phase); };
  if (!water && !oil)
    throw common::ConfigError(scene.file, "/fluid_blocks",
                              "the scene has no fluid: nothing for " + checkpoint + " to move");
  if ((water && !knows("water")) || (oil && !knows("oil")))
    throw common::ConfigError(
        scene.file, oil && !knows("oil") ? "/leaks" : "/fluid_blocks",
        "the scene has " + std::string(oil && !knows("oil") ? "oil" : "water") + ", a phase " +
            checkpoint + " was not trained on (it knows " + types.dump() + ")");
}

gnn::Bounds bounds_of(const sph::Aabb& domain) {
  gnn::Bounds b;
  for (int d = 0; d < 3; ++d) b[size_t(d)] = {double(domain.min[d]), double(domain.max[d])};
  return b;
}

sph::LoadedScene load_predicted_scene(const PredictOptions& o) {
  std::vector<std::string> overrides = o.overrides;
  if (o.end_time > 0) overrides.push_back("/end_time=" + text(o.end_time));
  return sph::load_scene(o.scene_file, overrides);
}

common::OutputFolderPolicy output_policy(const PredictOptions& o) {
  common::OutputFolderPolicy policy;
  policy.markers = {"metadata.json", "trajectory.h5", "stats.json"};
  policy.replace = true;
  policy.inputs = {o.scene_file, o.checkpoint};
  if (!o.initial_state.empty()) policy.inputs.push_back(o.initial_state);
  policy.log = o.log;
  return policy;
}

// The frame the forecast starts from: 0, or that of a saved state, which must be before the end.
int first_predicted_frame(const sph::Simulation& sim, const sph::LoadedScene& scene,
                          const std::string& initial_state) {
  const double frame_dt = sph::shortest_decimal(scene.config.output.frame_dt);
  const int first = int(std::llround(sim.time() / frame_dt));
  if (first >= sph::frame_count(scene.config))
    throw common::ConfigError(initial_state, "/time",
                              "the state is at t = " + text(sim.time()) +
                                  " s, at or after the scene's /end_time " +
                                  text(scene.config.end_time) +
                                  " s: nothing is left to predict (raise it with --end-time)");
  return first;
}

// --relax: that many iterations of the scene's density correction on every learned frame.
gnn::FrameCorrection relaxation_hook(const sph::SceneConfig& scene, int iterations) {
  if (iterations <= 0) return {};
  return gnn::relaxation_correction(std::make_shared<sph::DensityRelaxation>(scene), iterations);
}

// spill-sim run's metadata.json, saying which model predicted it.
nlohmann::json predict_metadata(const sph::Simulation& sim, const sph::LoadedScene& scene,
                                int frames, const PredictOptions& o,
                                const gnn::LoadedCheckpoint& checkpoint) {
  const std::string model = checkpoint.simulator->model().name();
  nlohmann::json metadata = sph::run_metadata(sim, scene, frames);
  metadata["predicted_by"] = {
      {"checkpoint", o.checkpoint},
      {"model", model},
      {"weights_checksum", checkpoint.payload_checksum},
      {"relax_iterations", o.relax},
      {"note",
       "positions and oil fractions from the learned simulator; the scene's emitters, inflow, "
       "outflow and domain released and retired particles between its frames"}};
  metadata["solver"] = model;
  return metadata;
}

// stats.json's summary of a forecast.
nlohmann::json predict_summary(const sph::Simulation& sim, const gnn::SceneRollout& stepper,
                               double wall_s, int frames, double start_time,
                               const PredictOptions& o, const std::string& model) {
  nlohmann::json summary = {
      {"wall_s", wall_s},
      {"frames", frames},
      {"wall_s_per_frame", wall_s / double(std::max(1, frames))},
      {"simulated_s", sim.time() - start_time},
      {"fluid_particles", sim.fluid().active_count()},
      {"boundary_particles", sim.boundary().size()},
      {"threads", o.threads},
      {"model", model},
      {"retired", stepper.retired().retired},
      {"left_domain", stepper.retired().left_domain},
      {"note",
       "wall_s: the learned frames with their sources, sinks and recording (pictures excluded "
       "only when --png is off); left_domain: particles the model moved out of the domain, "
       "which a solver run would stop on"}};
  if (const sph::RiverFlow* flow = sim.flow())
    summary["flow"] = {{"emitted", flow->emitted()},
                       {"retired", flow->retired()},
                       {"oil_left_m3", flow->oil_left_volume()},
                       {"skipped_inflow_layers", flow->skipped_layers()},
                       {"skipped_note",
                        "inflow layers the pool of returned water could not fill: the forecast "
                        "backed the reach up (a solver run stops there)"}};
  return summary;
}

}  // namespace

nlohmann::json run_predict(const PredictOptions& o) {
  const sph::LoadedScene scene = load_predicted_scene(o);
  gnn::LoadedCheckpoint checkpoint = gnn::load_checkpoint(o.checkpoint);
  check_scene_fits(checkpoint.data, scene, o.checkpoint);
  gnn::GraphModel& model = checkpoint.simulator->model();
  model.eval();
  gnn::configure_runtime(
      o.blas_threads > 0 ? gnn::RuntimeSettings{o.threads, o.blas_threads}
                         : gnn::inference_runtime(o.threads, model.infers_on_one_blas_thread()));

  common::OutputFolder output(o.out_dir, output_policy(o));
  const fs::path& staging = output.staging();

  sph::Simulation sim(scene.config);
  if (!o.initial_state.empty()) sim.load_state(o.initial_state);
  const int frames = sph::frame_count(scene.config);
  const double frame_dt = sph::shortest_decimal(scene.config.output.frame_dt);
  const int first = first_predicted_frame(sim, scene, o.initial_state);
  // The wall-distance features are measured to this scene's domain, as the data's were to its.
  gnn::LearnedSimulator learned(checkpoint.simulator->model_ptr(),
                                checkpoint.simulator->normalisation(), bounds_of(sim.domain()),
                                scene.config.particle_radius);
  gnn::SceneRollout stepper(learned, sim, gnn::material_table(scene.resolved.at("materials")),
                            frame_dt, scene.file);
  const gnn::FrameCorrection correct = relaxation_hook(scene.config, o.relax);
  common::write_file_atomically(
      staging / "metadata.json",
      predict_metadata(sim, scene, frames - first, o, checkpoint).dump(2) + "\n");
  // The learned frames leave density and pressure as they were: vtk/ has neither.
  sph::RunRecorder recorder(sim, scene.config, {o.png, false, o.vtk, /*solver_state=*/false},
                            staging);
  recorder.record(sim, first);

  common::ProgressReporter progress(o.log ? *o.log : std::cerr, o.terminal, frames,
                                    "predicting " + scene.config.name + " with " + model.name());
  nlohmann::json frame_list = nlohmann::json::array();
  frame_list.push_back(
      {{"t", sim.time()}, {"wall_s", 0.0}, {"active", sim.fluid().active_count()}});
  const auto start = std::chrono::steady_clock::now();
  for (int frame = first + 1; frame <= frames; ++frame) {
    common::throw_if_stopped(
        o.stop, [&] { return "before frame " + std::to_string(frame) + "; nothing written"; });
    const auto t0 = std::chrono::steady_clock::now();
    const sph::ExternalFrameStats retired = stepper.advance(frame, correct);
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    recorder.record(sim, frame);
    frame_list.push_back({{"t", sim.time()},
                          {"wall_s", wall},
                          {"active", sim.fluid().active_count()},
                          {"retired", retired.retired},
                          {"left_domain", retired.left_domain}});
    if (const sph::RiverFlow* flow = sim.flow())
      frame_list.back()["oil_left_m3"] = flow->oil_left_volume();
    if (o.log) progress.update(frame, "t = " + text(sim.time()) + " s");
  }
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  recorder.close_trajectory();
  const nlohmann::json summary =
      predict_summary(sim, stepper, wall_s, frames - first, first * frame_dt, o, model.name());
  common::write_file_atomically(
      staging / "stats.json",
      nlohmann::json{{"frames", frame_list}, {"summary", summary}}.dump(2) + "\n");
  if (o.png)
    sph::encode_animation(staging, scene.config.terrain_grid ? "river" : "side", first,
                          1 / frame_dt, o.log);
  recorder.write_metrics();
  sph::write_run_report(staging);
  if (o.log) progress.finish(std::to_string(frames - first) + " learned frames");
  output.commit();
  return summary;
}

}  // namespace infer
