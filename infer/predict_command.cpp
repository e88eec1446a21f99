#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <numeric>
#include <sstream>

#include "common/checked_file.h"
#include "common/config_error.h"
#include "common/exit_codes.h"
#include "common/number_text.h"
#include "common/output_folder.h"
#include "common/progress.h"
#include "common/stop_signals.h"
#include "gnn/eval/scene_rollout.h"
#include "gnn/eval/spill_measures.h"
#include "gnn/runtime/runtime.h"
#include "gnn/training/checkpoint.h"
#include "infer/commands.h"
#include "infer/forecast_ensemble.h"
#include "infer/map_views.h"
#include "sph/core/config.h"
#include "sph/io/animation.h"
#include "sph/io/run_metadata.h"
#include "sph/io/run_recorder.h"
#include "sph/io/run_report.h"
#include "sph/scene/scene_loader.h"
#include "sph/simulation/density_relaxation.h"
#include "sph/simulation/frame_loop.h"
#include "sph/simulation/spill_measurement.h"

namespace infer {
namespace fs = std::filesystem;

namespace {

// A model runs only on scenes like its data: the same frame interval, particle size and graph
// radius (its features are in those units), and fluid phases it has seen.
void check_scene_fits(const nlohmann::json& data, const sph::LoadedScene& scene,
                      const std::string& checkpoint) {
  const sph::SceneConfig& s = scene.config;
  const auto require_equal = [&](const char* what, const char* pointer, double trained,
                                 double given) {
    if (std::abs(trained - given) > 1e-6 * std::abs(trained))
      throw common::ConfigError(scene.file, pointer,
                                std::string(what) + " is " + common::number_text(given) + ", but " +
                                    checkpoint + " was trained on data with " +
                                    common::number_text(trained) +
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

// The scene with --end-time applied; refuses members on a scene with no river leak to measure.
sph::LoadedScene load_predicted_scene(const PredictOptions& o) {
  if (o.members < 1) throw common::InputError("predict: --members must be at least 1");
  std::vector<std::string> overrides = o.overrides;
  if (o.end_time > 0) overrides.push_back("/end_time=" + common::number_text(o.end_time));
  sph::LoadedScene scene = sph::load_scene(o.scene_file, overrides);
  if (o.members > 1 && !sph::river_spill_metrics(scene.config))
    throw common::ConfigError(scene.file, "/leaks",
                              "--members summarises a river leak's spill metrics; the scene has "
                              "no leak over terrain");
  return scene;
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
                              "the state is at t = " + common::number_text(sim.time()) +
                                  " s, at or after the scene's /end_time " +
                                  common::number_text(scene.config.end_time) +
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
      {"members", o.members},
      {"note",
       "positions and oil fractions from the learned simulator; the scene's emitters, inflow, "
       "outflow and domain released and retired particles between its frames"}};
  if (o.members > 1) {
    metadata["predicted_by"]["member_jitter_diameters"] = o.member_jitter;
    metadata["predicted_by"]["members_note"] =
        "member 1 is the forecast of this folder (trajectory.h5, spill.json, pictures), from the "
        "unperturbed start; members 2..K start with every active particle's input history moved "
        "by a uniform offset of up to member_jitter_diameters particle diameters per coordinate, "
        "seeded by the member's number; ensemble.json, members/ and oiling.png summarise them";
  }
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

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::unique_ptr<sph::Simulation> member_simulation(const sph::LoadedScene& scene,
                                                   const std::string& initial_state) {
  auto sim = std::make_unique<sph::Simulation>(scene.config);
  if (!initial_state.empty()) sim->load_state(initial_state);
  return sim;
}

std::vector<common::Point> active_points(const sph::FluidParticles& f) {
  std::vector<common::Point> out(f.active_count());
  for (sph::Index i = 0; i < f.active_count(); ++i) out[i] = f.position[i].cast<float>();
  return out;
}

// What every member of a forecast ensemble leaves behind: its spill metrics (members/NN/), the
// oil's centroid per frame, and its oiled cells at the oiling picture's moments (the first
// member's water drawn under them).
class EnsembleRecorder {
 public:
  EnsembleRecorder(const sph::SceneConfig& scene, int first, int frames)
      : scene_(scene),
        first_(first),
        oiling_(scene.particle_diameter(),
                quarter_frames(std::min(std::max(first, leak_frame(scene)), frames - 1), frames)) {}

  void start_member() {
    spill_ = sph::river_spill_metrics(scene_);
    centroids_.clear();
  }
  void measure(const sph::Simulation& sim, int frame) {
    sph::measure_spill(*spill_, sim);
    centroids_.push_back(oil_centroid(sim.fluid()));
    oiling_.measure(frame, sim.fluid());
    if (tracks_.empty()) {
      const auto& moments = oiling_.frames();
      if (std::find(moments.begin(), moments.end(), frame) != moments.end())
        water_.push_back(active_points(sim.fluid()));
    }
  }
  void end_member() {
    oiling_.end_member();
    tracks_.push_back(member_track(*spill_, centroids_));
    spill_json_.push_back(spill_->to_json());
    times_.clear();
    for (const auto& f : spill_->frames()) times_.push_back(f.t);
  }

  // ensemble.json, members/NN/spill.json and oiling.png into `folder`.
  void write(const fs::path& folder, const sph::Simulation& sim) const {
    for (size_t k = 0; k < spill_json_.size(); ++k) {
      std::ostringstream name;
      name << std::setw(2) << std::setfill('0') << k + 1;
      const fs::path dir = folder / "members" / name.str();
      fs::create_directories(dir);
      common::write_file_atomically(dir / "spill.json", spill_json_[k].dump(2) + "\n");
    }
    nlohmann::json summary = ensemble_summary(tracks_, times_);
    nlohmann::json moments = nlohmann::json::array();
    for (int f : oiling_.frames()) moments.push_back(times_.at(size_t(f - first_)));
    summary["oiling_png"] = {
        {"t", moments},
        {"note",
         "oiling.png: the share of members with oil in each top-view cell a particle diameter "
         "wide (pale blue for few, near-black for all), at each t, then every cell any frame of "
         "a member oiled; over the first member's fluid"}};
    common::write_file_atomically(folder / "ensemble.json", summary.dump(2) + "\n");
    const common::FrameRenderer renderer(
        boundary_points(sim.boundary()),
        common::Bounds{sim.domain().min.cast<float>(), sim.domain().max.cast<float>()},
        float(scene_.particle_radius), 480);
    common::write_png((folder / "oiling.png").string(),
                      image_grid({oiling_.render(renderer, water_, float(sim.domain().max.z()),
                                                 int(tracks_.size()))}));
  }

 private:
  // The frame the first leak starts in: the pictures before it would show no oil.
  static int leak_frame(const sph::SceneConfig& scene) {
    double start = scene.end_time;
    for (const auto& leak : scene.leaks) start = std::min(start, double(leak.start));
    return int(std::floor(start / sph::shortest_decimal(scene.output.frame_dt)));
  }
  // A quarter, half, three quarters and all of the way from `first` to `frames` (> first): the
  // last frame at least, also for a forecast that ends before its leak starts.
  static std::vector<int> quarter_frames(int first, int frames) {
    std::vector<int> out;
    for (int q = 1; q <= 4; ++q) {
      const int f = first + int(std::lround(double(frames - first) * q / 4.0));
      if (f > first && (out.empty() || out.back() != f)) out.push_back(f);
    }
    return out;
  }
  static std::vector<common::Point> boundary_points(const sph::BoundaryParticles& b) {
    std::vector<common::Point> out(b.size());
    for (sph::Index i = 0; i < b.size(); ++i) out[i] = b.position[i].cast<float>();
    return out;
  }

  const sph::SceneConfig& scene_;
  int first_;  // the forecast's first frame (its start)
  OilingMap oiling_;
  std::unique_ptr<sph::SpillMetrics> spill_;
  std::vector<std::pair<double, double>> centroids_;
  std::vector<MemberTrack> tracks_;
  std::vector<nlohmann::json> spill_json_;
  std::vector<double> times_;
  std::vector<std::vector<common::Point>> water_;  // the first member's, at the moments
};

// stats.json's entry for one learned frame of the first member.
nlohmann::json learned_frame_record(const sph::Simulation& sim, double wall_s,
                                    const sph::ExternalFrameStats& retired) {
  nlohmann::json record = {{"t", sim.time()},
                           {"wall_s", wall_s},
                           {"active", sim.fluid().active_count()},
                           {"retired", retired.retired},
                           {"left_domain", retired.left_domain}};
  if (const sph::RiverFlow* flow = sim.flow()) record["oil_left_m3"] = flow->oil_left_volume();
  return record;
}

// stats.json's "members": each member's wall time, and what they include.
nlohmann::json members_json(const PredictOptions& o, const std::vector<double>& member_wall_s,
                            long per_member) {
  double all = 0;
  for (double w : member_wall_s) all += w;
  return {{"count", o.members},
          {"member_jitter_diameters", o.member_jitter},
          {"wall_s", member_wall_s},
          {"wall_s_all", all},
          {"wall_s_per_frame", all / double(std::max(1L, per_member * o.members))},
          {"note",
           "wall_s: each member's learned frames with their sources, sinks and measures (the "
           "first also records this folder); start_up_s (loading the scene and the model, once) "
           "is apart"}};
}

}  // namespace

nlohmann::json run_predict(const PredictOptions& o) {
  const auto started = std::chrono::steady_clock::now();
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

  std::unique_ptr<sph::Simulation> sim = member_simulation(scene, o.initial_state);
  const int frames = sph::frame_count(scene.config);
  const double frame_dt = sph::shortest_decimal(scene.config.output.frame_dt);
  const int first = first_predicted_frame(*sim, scene, o.initial_state);
  // The wall-distance features are measured to this scene's domain, as the data's were to its.
  gnn::LearnedSimulator learned(checkpoint.simulator->model_ptr(),
                                checkpoint.simulator->normalisation(), bounds_of(sim->domain()),
                                scene.config.particle_radius);
  const torch::Tensor material = gnn::material_table(scene.resolved.at("materials"));
  const gnn::FrameCorrection correct = relaxation_hook(scene.config, o.relax);
  common::write_file_atomically(
      staging / "metadata.json",
      predict_metadata(*sim, scene, frames - first, o, checkpoint).dump(2) + "\n");
  const double start_up_s = seconds_since(started);

  const long per_member = frames - first;
  common::ProgressReporter progress(o.log ? *o.log : std::cerr, o.terminal, per_member * o.members,
                                    "predicting " + scene.config.name + " with " + model.name());
  std::optional<EnsembleRecorder> ensemble;
  if (o.members > 1) ensemble.emplace(scene.config, first, frames);
  std::vector<double> member_wall_s;
  nlohmann::json frame_list = nlohmann::json::array();
  nlohmann::json summary;
  for (int member = 1; member <= o.members; ++member) {
    if (member > 1) sim = member_simulation(scene, o.initial_state);
    gnn::SceneRollout stepper(learned, *sim, material, frame_dt, scene.file);
    if (member > 1)
      stepper.jitter_start(o.member_jitter * scene.config.particle_diameter(), uint64_t(member));
    // The first member is this folder's forecast: recorded as spill-sim run records.
    // The learned frames leave density and pressure as they were: vtk/ has neither.
    std::optional<sph::RunRecorder> recorder;
    if (member == 1) {
      recorder.emplace(*sim, scene.config,
                       sph::RecorderOptions{o.png, false, o.vtk, /*solver_state=*/false}, staging);
      recorder->record(*sim, first);
      frame_list.push_back(
          {{"t", sim->time()}, {"wall_s", 0.0}, {"active", sim->fluid().active_count()}});
    }
    if (ensemble) {
      ensemble->start_member();
      ensemble->measure(*sim, first);
    }
    const auto member_start = std::chrono::steady_clock::now();
    for (int frame = first + 1; frame <= frames; ++frame) {
      common::throw_if_stopped(
          o.stop, [&] { return "before frame " + std::to_string(frame) + "; nothing written"; });
      const auto t0 = std::chrono::steady_clock::now();
      const sph::ExternalFrameStats retired = stepper.advance(frame, correct);
      const double wall = seconds_since(t0);
      if (ensemble) ensemble->measure(*sim, frame);
      if (recorder) {
        recorder->record(*sim, frame);
        frame_list.push_back(learned_frame_record(*sim, wall, retired));
      }
      if (o.log)
        progress.update((member - 1) * per_member + frame - first,
                        (o.members > 1 ? "member " + std::to_string(member) + ", " : "") +
                            "t = " + common::number_text(sim->time()) + " s");
    }
    member_wall_s.push_back(seconds_since(member_start));
    if (ensemble) ensemble->end_member();
    if (recorder) {
      recorder->close_trajectory();
      summary = predict_summary(*sim, stepper, member_wall_s.back(), frames - first,
                                first * frame_dt, o, model.name());
      recorder->write_metrics();
    }
  }
  summary["start_up_s"] = start_up_s;
  if (ensemble) {
    ensemble->write(staging, *sim);
    summary["members"] = members_json(o, member_wall_s, per_member);
  }
  common::write_file_atomically(
      staging / "stats.json",
      nlohmann::json{{"frames", frame_list}, {"summary", summary}}.dump(2) + "\n");
  if (o.png)
    sph::encode_animation(staging, scene.config.terrain_grid ? "river" : "side", first,
                          1 / frame_dt, o.log);
  sph::write_run_report(staging);
  if (o.log)
    progress.finish(std::to_string(per_member * o.members) + " learned frames" +
                    (o.members > 1 ? " in " + std::to_string(o.members) + " members" : ""));
  output.commit();
  return summary;
}

}  // namespace infer
