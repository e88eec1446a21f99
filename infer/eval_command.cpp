#include <filesystem>
#include <fstream>

#include "common/checked_file.h"
#include "common/exit_codes.h"
#include "common/progress.h"
#include "common/stop_signals.h"
#include "common/svg_plot.h"
#include "infer/commands.h"
#include "infer/loaded_data.h"
#include "infer/trajectory_scores.h"

namespace infer {
namespace fs = std::filesystem;

namespace {

const std::vector<int64_t> kHorizons = {1, 5, 10, 20, 50};

nlohmann::json optional_json(const std::optional<double>& v) {
  return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}

// Per horizon (and "all" = mean over every rollout frame) of one per-frame series per
// trajectory, averaged over the trajectories that reach the horizon.
nlohmann::json by_horizon(const std::vector<const std::vector<double>*>& series) {
  nlohmann::json out = nlohmann::json::object();
  for (int64_t h : kHorizons) {
    std::vector<double> values;
    for (const auto* s : series)
      if (int64_t(s->size()) >= h) values.push_back((*s)[size_t(h - 1)]);
    if (!values.empty()) out[std::to_string(h)] = mean(values);
  }
  std::vector<double> all;
  for (const auto* s : series) all.push_back(mean(*s));
  out["all"] = mean(all);
  return out;
}

nlohmann::json by_horizon(const std::vector<TrajectoryScores>& scores,
                          std::vector<double> TrajectoryScores::*series) {
  std::vector<const std::vector<double>*> each;
  for (const auto& s : scores) each.push_back(&(s.*series));
  return by_horizon(each);
}

// A series of one side's measures (FrameMeasures), e.g. the prediction's compression.
nlohmann::json by_horizon(const std::vector<TrajectoryScores>& scores,
                          FrameMeasures TrajectoryScores::*side,
                          std::vector<double> FrameMeasures::*series) {
  std::vector<const std::vector<double>*> each;
  for (const auto& s : scores) each.push_back(&(s.*side.*series));
  return by_horizon(each);
}

// Nothing to score is not a perfect score: a split without trajectories, or whose fluid is
// never present, is refused.
void check_scorable(const LoadedData& d, const EvalOptions& o) {
  if (d.trajectories.empty())
    throw gnn::DatasetError(o.common.data_dir + "/" + o.common.split + ".h5: no trajectories");
  for (const auto& t : d.trajectories)
    if (t.particle_type.size(0) == 0 || !t.active.any().item<bool>())
      throw gnn::DatasetError(t.source + ": no fluid particle is ever active; nothing to score");
}

// The rollout of one trajectory from o.from, scored; `row` gets its line of eval.json.
TrajectoryScores score_trajectory(const LoadedData& d, const gnn::Trajectory& t,
                                  const EvalOptions& o, nlohmann::json& row) {
  const int64_t available = t.frames() - 1 - o.from;
  if (o.from < 0 || available < 1)
    throw common::InputError("--from " + std::to_string(o.from) + ": " + t.source + " has " +
                             std::to_string(t.frames()) + " frames");
  const int64_t frames = o.frames > 0 ? std::min<int64_t>(o.frames, available) : available;
  const auto scene = spill_scene_of(t, o.common.log);
  TrajectoryScores s = score_rollout(
      *d.checkpoint.simulator, t, d.metadata, scene.get(),
      recorded_measures(scene.get(), t, o.from, frames), o.from, frames,
      sources_of(o.common.replay_recorded_sources), o.common.relax, nullptr, [&](int64_t k) {
        common::throw_if_stopped(o.common.stop, [&] {
          return "at frame " + std::to_string(k) + " of " + t.source + "; nothing written";
        });
      });
  row = {{"source", t.source},
         {"frames", frames},
         {"one_step_mse", optional_json(s.one_step_mse)},
         {"rollout_mse_all", mean(s.mse)},
         {"rollout_mse_last", s.mse.back()},
         {"oil_iou_mean", mean(s.iou)},
         {"slick_area_error", optional_json(slick_area_error(s))},
         {"front_distance_error_m", optional_json(front_distance_error(s))},
         {"bank_contact_time_error_s", optional_json(bank_contact_time_error(s))},
         {"watch_arrival_time_error_s", optional_json(watch_arrival_time_error(s))},
         {"wall_s_per_frame", s.wall_s_per_frame},
         {"skipped_inflow_layers", s.skipped_inflow_layers},
         {"active_deviation_max", s.active_deviation_max}};
  return s;
}

const char* const kEvalUnits =
    "one_step_mse and rollout_mse: squared position error in m^2, averaged over the 3 "
    "dimensions and over the fluid particles active in both the prediction and the "
    "recording; horizons are frames after from_frame ('all' = mean over every rollout "
    "frame); mmd: squared maximum mean discrepancy of the fluid clouds (Gaussian kernel, "
    "bandwidth = connectivity radius); kinetic_energy_error: |KE_pred - KE_true| / KE_true of "
    "the mean kinetic energy per unit mass; oil_iou: intersection over union of top-view oil "
    "masks on cells of one particle diameter, oil being a particle whose oil fraction "
    "(recorded, or "
    "predicted by the model) is at least 1/2 at that frame";

// eval.json: the figures over the split by horizon, and a line per trajectory.
nlohmann::json eval_result(const LoadedData& d, const EvalOptions& o,
                           const std::vector<TrajectoryScores>& scores,
                           const nlohmann::json& per_trajectory) {
  std::vector<double> one_step, wall, sph;
  for (const auto& s : scores) {
    one_step.push_back(s.one_step_mse.value_or(0.0));
    wall.push_back(s.wall_s_per_frame);
    if (s.sph_seconds_per_frame > 0) sph.push_back(s.sph_seconds_per_frame);
  }
  return {{"checkpoint", o.common.checkpoint},
          {"model", d.checkpoint.simulator->model().name()},
          {"data", o.common.data_dir},
          {"split", o.common.split},
          {"trajectories", scores.size()},
          {"from_frame", o.from},
          {"units", kEvalUnits},
          {"one_step_mse", mean(one_step)},
          {"rollout_mse", by_horizon(scores, &TrajectoryScores::mse)},
          {"mmd", by_horizon(scores, &TrajectoryScores::mmd)},
          {"kinetic_energy_error", by_horizon(scores, &TrajectoryScores::ke_error)},
          {"oil_iou", by_horizon(scores, &TrajectoryScores::iou)},
          {"wall_s_per_frame", mean(wall)},
          {"sph_seconds_per_frame", mean(sph)},
          {"threads", o.common.threads},
          {"relax_iterations", o.common.relax},
          {"sources", sources_name(sources_of(o.common.replay_recorded_sources))},
          {"compression_mean",
           by_horizon(scores, &TrajectoryScores::predicted, &FrameMeasures::compression_mean)},
          {"compression_p95",
           by_horizon(scores, &TrajectoryScores::predicted, &FrameMeasures::compression_p95)},
          {"recorded_compression_mean",
           by_horizon(scores, &TrajectoryScores::recorded, &FrameMeasures::compression_mean)},
          {"per_trajectory", per_trajectory}};
}

// error_vs_horizon.svg: each trajectory's rollout error by frame.
void write_error_plot(const fs::path& file, const LoadedData& d,
                      const std::vector<TrajectoryScores>& scores) {
  std::vector<common::PlotSeries> series;
  for (size_t k = 0; k < scores.size(); ++k) {
    common::PlotSeries p{
        d.trajectories[k].source.substr(d.trajectories[k].source.rfind('/') + 1), {}, {}};
    for (size_t h = 0; h < scores[k].mse.size(); ++h) {
      p.x.push_back(double(h + 1));
      p.y.push_back(scores[k].mse[h]);
    }
    series.push_back(p);
  }
  common::write_line_plot(file.string(),
                          "Rollout position error of " + d.checkpoint.simulator->model().name(),
                          "frames after the start", "position MSE (m^2)", series, true);
}

}  // namespace

void run_eval(const EvalOptions& o) {
  common::OutputFolder output(o.common.out_dir,
                              output_policy(o.common, {"eval.json", "error_vs_horizon.svg"}));
  LoadedData d = load_data(o.common);
  std::vector<TrajectoryScores> scores;
  nlohmann::json per_trajectory = nlohmann::json::array();
  std::unique_ptr<common::ProgressReporter> progress;
  if (o.common.log)
    progress = std::make_unique<common::ProgressReporter>(*o.common.log, false,
                                                          int64_t(d.trajectories.size()), "eval");
  check_scorable(d, o);
  for (size_t k = 0; k < d.trajectories.size(); ++k) {
    nlohmann::json row;
    scores.push_back(score_trajectory(d, d.trajectories[k], o, row));
    per_trajectory.push_back(row);
    if (progress) progress->update(int64_t(k + 1), d.trajectories[k].source);
  }
  if (progress) progress->finish("");
  const nlohmann::json result = eval_result(d, o, scores, per_trajectory);
  const fs::path out = output.staging();
  common::write_file_atomically((out / "eval.json").string(), result.dump(2) + "\n");
  write_error_plot(out / "error_vs_horizon.svg", d, scores);
  output.commit();
  if (o.common.log)
    *o.common.log << "one-step MSE " << result["one_step_mse"].get<double>()
                  << " m^2, rollout MSE (all frames) " << result["rollout_mse"]["all"].get<double>()
                  << " m^2; written to " << (output.target() / "eval.json").string() << "\n";
}

}  // namespace infer
