#include <filesystem>
#include <fstream>
#include <map>
#include <numeric>

#include "common/checked_file.h"
#include "common/exit_codes.h"
#include "common/progress.h"
#include "common/svg_plot.h"
#include "gnn/data/frame_window.h"
#include "gnn/eval/metrics.h"
#include "gnn/eval/rollout.h"
#include "infer/commands.h"
#include "infer/loaded_data.h"

namespace infer {
namespace fs = std::filesystem;

namespace {

const std::vector<int64_t> kHorizons = {1, 5, 10, 20, 50};

struct TrajectoryScores {
  double one_step_mse = 0;
  std::vector<double> mse, mmd, ke_error, iou;  // per rollout frame 1..F
  double wall_s_per_frame = 0, sph_seconds_per_frame = 0;
};

// Velocities (m/s) between frames k-1 and k of particles active in both.
torch::Tensor frame_velocity(const torch::Tensor& position, const torch::Tensor& active, int64_t k,
                             double dt, torch::Tensor& both) {
  both = active[k] & active[k - 1];
  return (position[k] - position[k - 1]) / dt;
}

TrajectoryScores score(gnn::LearnedSimulator& sim, const gnn::Trajectory& t,
                       const gnn::DatasetMetadata& m, int64_t from, int64_t frames) {
  TrajectoryScores s;
  std::vector<int64_t> one_step_frames;
  const int64_t first = gnn::kWindow - 1, last = t.frames() - 2;
  const int64_t stride = std::max<int64_t>(1, (last - first + 1) / 20);
  for (int64_t f = first; f <= last; f += stride) one_step_frames.push_back(f);
  s.one_step_mse = gnn::one_step_position_mse(sim, t, one_step_frames, m.frame_dt);

  auto r = gnn::rollout(sim, t, from, frames, m.frame_dt);
  auto truth = t.position.slice(0, from, from + frames + 1);
  auto truth_active = t.active.slice(0, from, from + frames + 1);
  const double cell = 2 * m.particle_radius;
  const auto oil = t.particle_type == gnn::kOil;
  for (int64_t k = 1; k <= frames; ++k) {
    auto active = r.active[k] & truth_active[k];
    s.mse.push_back(gnn::position_mse(r.position[k], truth[k], active));
    s.mmd.push_back(gnn::mmd_rbf(r.position[k].index({active}), truth[k].index({active}),
                                 m.connectivity_radius));
    torch::Tensor both_p, both_t;
    auto vp = frame_velocity(r.position, r.active, k, m.frame_dt, both_p);
    auto vt = frame_velocity(truth, truth_active, k, m.frame_dt, both_t);
    const double ke_p = gnn::mean_kinetic_energy(vp, both_p & both_t);
    const double ke_t = gnn::mean_kinetic_energy(vt, both_p & both_t);
    s.ke_error.push_back(ke_t > 0 ? std::abs(ke_p - ke_t) / ke_t : 0.0);
    s.iou.push_back(gnn::top_view_iou(r.position[k].index({active & oil}).slice(1, 0, 2),
                                      truth[k].index({active & oil}).slice(1, 0, 2), cell));
  }
  s.wall_s_per_frame =
      std::accumulate(r.frame_seconds.begin(), r.frame_seconds.end(), 0.0) / double(frames);
  s.sph_seconds_per_frame = t.sph_seconds_per_frame;
  return s;
}

double mean(const std::vector<double>& v) {
  return v.empty() ? 0.0 : std::accumulate(v.begin(), v.end(), 0.0) / double(v.size());
}

// Per horizon (and "all" = mean over every rollout frame), averaged over trajectories that reach
// the horizon.
nlohmann::json by_horizon(const std::vector<TrajectoryScores>& scores,
                          std::vector<double> TrajectoryScores::*series) {
  nlohmann::json out = nlohmann::json::object();
  for (int64_t h : kHorizons) {
    std::vector<double> values;
    for (const auto& s : scores)
      if (int64_t((s.*series).size()) >= h) values.push_back((s.*series)[size_t(h - 1)]);
    if (!values.empty()) out[std::to_string(h)] = mean(values);
  }
  std::vector<double> all;
  for (const auto& s : scores) all.push_back(mean(s.*series));
  out["all"] = mean(all);
  return out;
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
  // Nothing to score is not a perfect score: a split without trajectories, or whose fluid is
  // never present, is refused.
  if (d.trajectories.empty())
    throw gnn::DatasetError(o.common.data_dir + "/" + o.common.split + ".h5: no trajectories");
  for (const auto& t : d.trajectories)
    if (t.particle_type.size(0) == 0 || !t.active.any().item<bool>())
      throw gnn::DatasetError(t.source + ": no fluid particle is ever active; nothing to score");
  for (size_t k = 0; k < d.trajectories.size(); ++k) {
    const auto& t = d.trajectories[k];
    const int64_t available = t.frames() - 1 - o.from;
    if (o.from < 0 || available < 1)
      throw common::InputError("--from " + std::to_string(o.from) + ": " + t.source + " has " +
                               std::to_string(t.frames()) + " frames");
    const int64_t frames = o.frames > 0 ? std::min<int64_t>(o.frames, available) : available;
    scores.push_back(score(*d.checkpoint.simulator, t, d.metadata, o.from, frames));
    const auto& s = scores.back();
    per_trajectory.push_back({{"source", t.source},
                              {"frames", frames},
                              {"one_step_mse", s.one_step_mse},
                              {"rollout_mse_all", mean(s.mse)},
                              {"rollout_mse_last", s.mse.back()},
                              {"oil_iou_mean", mean(s.iou)},
                              {"wall_s_per_frame", s.wall_s_per_frame}});
    if (progress) progress->update(int64_t(k + 1), t.source);
  }
  if (progress) progress->finish("");
  std::vector<double> one_step, wall, sph;
  for (const auto& s : scores) {
    one_step.push_back(s.one_step_mse);
    wall.push_back(s.wall_s_per_frame);
    if (s.sph_seconds_per_frame > 0) sph.push_back(s.sph_seconds_per_frame);
  }
  nlohmann::json result = {
      {"checkpoint", o.common.checkpoint},
      {"model", d.checkpoint.simulator->model().name()},
      {"data", o.common.data_dir},
      {"split", o.common.split},
      {"trajectories", scores.size()},
      {"from_frame", o.from},
      {"units",
       "one_step_mse and rollout_mse: squared position error in m^2, averaged over the 3 "
       "dimensions and over the fluid particles active in both the prediction and the "
       "recording; horizons are frames after from_frame ('all' = mean over every rollout "
       "frame); mmd: squared maximum mean discrepancy of the fluid clouds (Gaussian kernel, "
       "bandwidth = connectivity radius); kinetic_energy_error: |KE_pred - KE_true| / KE_true of "
       "the mean kinetic energy per unit mass; oil_iou: intersection over union of top-view oil "
       "masks on cells of one particle diameter"},
      {"one_step_mse", mean(one_step)},
      {"rollout_mse", by_horizon(scores, &TrajectoryScores::mse)},
      {"mmd", by_horizon(scores, &TrajectoryScores::mmd)},
      {"kinetic_energy_error", by_horizon(scores, &TrajectoryScores::ke_error)},
      {"oil_iou", by_horizon(scores, &TrajectoryScores::iou)},
      {"wall_s_per_frame", mean(wall)},
      {"sph_seconds_per_frame", mean(sph)},
      {"threads", o.common.threads},
      {"per_trajectory", per_trajectory}};

  const fs::path out = output.staging();
  const std::string json_file = (out / "eval.json").string();
  common::write_file_atomically(json_file, result.dump(2) + "\n");
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
  common::write_line_plot((out / "error_vs_horizon.svg").string(),
                          "Rollout position error of " + d.checkpoint.simulator->model().name(),
                          "frames after the start", "position MSE (m^2)", series, true);
  output.commit();
  if (o.common.log)
    *o.common.log << "one-step MSE " << result["one_step_mse"].get<double>()
                  << " m^2, rollout MSE (all frames) " << result["rollout_mse"]["all"].get<double>()
                  << " m^2; written to " << (output.target() / "eval.json").string() << "\n";
}

}  // namespace infer
