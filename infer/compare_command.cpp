// spill-infer compare: every model rolled out from the same frames of the same trajectories,
// scored alike, in one table and one picture (the paper's Table 5 and Fig. 13-17).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <sstream>

#include "common/checked_file.h"
#include "common/exit_codes.h"
#include "common/image_writer.h"
#include "common/output_folder.h"
#include "common/progress.h"
#include "common/stop_signals.h"
#include "gnn/data/frame_window.h"
#include "gnn/eval/bootstrap.h"
#include "gnn/eval/solver_rollout.h"
#include "gnn/runtime/runtime.h"
#include "gnn/training/checkpoint.h"
#include "infer/commands.h"
#include "infer/compare_report.h"
#include "infer/ensemble_scores.h"
#include "infer/map_views.h"
#include "infer/teacher_student_table.h"
#include "infer/trajectory_scores.h"

namespace infer {
namespace fs = std::filesystem;

namespace {

struct ComparedModel {
  std::string name, source;                          // row name; checkpoint file, or "built in"
  std::unique_ptr<gnn::LearnedSimulator> simulator;  // null for the ceiling (the data's solver)
};

// The ceiling's row: the data's own solver, from the same frame, positions jittered.
constexpr const char* kCeilingName = "sph_ceiling";

// A run's folder names its checkpoint (RUN/last.pt -> RUN); other files go by their stem.
std::string model_name(const std::string& checkpoint) {
  const fs::path p(checkpoint);
  if (p.filename() == "last.pt" && p.has_parent_path() && !p.parent_path().filename().empty())
    return p.parent_path().filename().string();
  return p.stem().string();
}

std::vector<ComparedModel> load_models(const CompareOptions& o, const gnn::DatasetMetadata& m) {
  std::vector<ComparedModel> models;
  std::map<std::string, int> seen;
  for (const auto& file : o.checkpoints) {
    gnn::LoadedCheckpoint c = gnn::load_checkpoint(file);
    gnn::check_data_fits(c.data, m, file);
    std::string name = model_name(file);
    if (seen[name]++ > 0) name += "_" + std::to_string(seen[name]);
    models.push_back({name, file, std::move(c.simulator)});
  }
  if (o.constant_velocity) {
    // The floor needs no training: built here with the dataset's own statistics.
    auto model = gnn::make_model(
        {{"model", "constant_velocity"}, {"radius", m.connectivity_radius}}, "--constant-velocity");
    models.push_back(
        {"constant_velocity", "built in",
         std::make_unique<gnn::LearnedSimulator>(
             model, gnn::Normalisation::from_metadata(m, 0.0, 0.0), m.bounds, m.particle_radius)});
  }
  if (o.ceiling_jitter > 0)
    models.push_back({kCeilingName,
                      "the dataset's scene and solver, positions jittered by " +
                          std::to_string(o.ceiling_jitter) + " particle diameters",
                      nullptr});
  for (auto& model : models) {
    if (!model.simulator) continue;
    model.simulator->to(gnn::parse_device(o.device));
    model.simulator->model().eval();
  }
  return models;
}

// Mean and spread over trajectories of one figure; trajectories without it are left out.
struct Figure {
  std::vector<double> values;
  void add(const std::optional<double>& v) {
    if (v) values.push_back(*v);
  }
};

// The value at frame h of a per-frame series (1-based), if the rollout reached it.
std::optional<double> at_horizon(const std::vector<double>& series, int64_t h) {
  if (int64_t(series.size()) < h) return std::nullopt;
  return series[size_t(h - 1)];
}

// The rollout times the forecast scores are read at: 1 s, 2 s and the leak's end.
const char* const kHorizonNames[] = {"1s", "2s", "leak_end"};

std::optional<double> horizon_seconds(const TrajectoryScores& s, const std::string& horizon) {
  if (horizon == "1s") return 1.0;
  if (horizon == "2s") return 2.0;
  return s.leak_end;
}

// The value of a per-frame series `seconds` after the start, where the rollout reached and
// defined it.
std::optional<double> at_time(const std::vector<double>& series,
                              const std::optional<double>& seconds, double frame_dt) {
  if (!seconds) return std::nullopt;
  const int64_t k = frame_at(*seconds, frame_dt);
  if (k < 1) return std::nullopt;
  const auto v = at_horizon(series, k);
  if (!v || !std::isfinite(*v)) return std::nullopt;
  return v;
}

std::string fss_key(size_t scale) {
  return "fss_" + std::to_string(int(std::lround(kFssScales[scale] * 100))) + "cm";
}

// Every figure of a row, in the order comparison.json lists them.
std::vector<std::string> figure_order() {
  std::vector<std::string> order = {
      "one_step_mse",         "rollout_mse_1s", "rollout_mse_5",   "rollout_mse_10",
      "rollout_mse_20",       "rollout_mse_50", "rollout_mse_all", "mmd",
      "kinetic_energy_error", "oil_iou_10",     "oil_iou_20",      "oil_iou_50"};
  for (const std::string h : kHorizonNames) {
    order.push_back("sinkhorn_oil_" + h);
    order.push_back("sinkhorn_fluid_" + h);
    for (size_t j = 0; j < std::size(kFssScales); ++j) order.push_back(fss_key(j) + "_" + h);
  }
  for (const std::string h : kHorizonNames)
    for (const char* key : {"crps_front_m_", "crps_slick_area_m2_", "crps_centroid_x_m_",
                            "crps_centroid_y_m_", "brier_watch_", "front_spread_m_"})
      order.push_back(key + h);
  order.push_back("crps_watch_arrival_s");
  for (const char* key : {"slick_area_error", "front_distance_error_m", "bank_contact_time_error_s",
                          "watch_arrival_time_error_s", "compression_mean", "compression_p95",
                          "seconds_per_frame", "seconds_per_simulated_second"})
    order.push_back(key);
  return order;
}

std::map<std::string, Figure> figures_of(const std::vector<TrajectoryScores>& scores,
                                         double frame_dt) {
  std::map<std::string, Figure> f;
  for (const auto& s : scores) {
    f["one_step_mse"].add(s.one_step_mse);
    for (int64_t h : {5, 10, 20, 50}) {
      f["rollout_mse_" + std::to_string(h)].add(at_horizon(s.mse, h));
      if (h >= 10) f["oil_iou_" + std::to_string(h)].add(at_horizon(s.iou, h));
    }
    f["rollout_mse_1s"].add(at_time(s.mse, 1.0, frame_dt));
    for (const std::string h : kHorizonNames) {
      const auto when = horizon_seconds(s, h);
      f["sinkhorn_oil_" + h].add(at_time(s.sinkhorn_oil, when, frame_dt));
      f["sinkhorn_fluid_" + h].add(at_time(s.sinkhorn_fluid, when, frame_dt));
      for (size_t j = 0; j < s.fss.size(); ++j)
        f[fss_key(j) + "_" + h].add(at_time(s.fss[j], when, frame_dt));
    }
    f["rollout_mse_all"].add(mean(s.mse));
    f["mmd"].add(mean(s.mmd));
    f["kinetic_energy_error"].add(mean(s.ke_error));
    f["slick_area_error"].add(slick_area_error(s));
    f["front_distance_error_m"].add(front_distance_error(s));
    f["bank_contact_time_error_s"].add(bank_contact_time_error(s));
    f["watch_arrival_time_error_s"].add(watch_arrival_time_error(s));
    if (!s.predicted.compression_mean.empty()) {
      f["compression_mean"].add(mean(s.predicted.compression_mean));
      f["compression_p95"].add(mean(s.predicted.compression_p95));
    }
    f["seconds_per_frame"].add(s.wall_s_per_frame);
    f["seconds_per_simulated_second"].add(s.wall_s_per_frame / frame_dt);
  }
  return f;
}

// One trajectory's figures from its members' scores: each figure the mean over the members that
// define it (so the bootstrap over trajectories sees one value per trajectory), then the
// ensemble's fair CRPS and Brier scores at the horizons.
void add_trajectory_figures(std::map<std::string, Figure>& f,
                            const std::vector<TrajectoryScores>& members, double frame_dt) {
  for (auto& [key, figure] : figures_of(members, frame_dt))
    if (!figure.values.empty()) f[key].add(mean(figure.values));
  const EnsembleScores e = score_ensemble(members, frame_dt);
  for (const std::string h : kHorizonNames) {
    const auto when = horizon_seconds(members.front(), h);
    f["crps_front_m_" + h].add(at_time(e.crps_front, when, frame_dt));
    f["crps_slick_area_m2_" + h].add(at_time(e.crps_slick_area, when, frame_dt));
    f["crps_centroid_x_m_" + h].add(at_time(e.crps_centroid_x, when, frame_dt));
    f["crps_centroid_y_m_" + h].add(at_time(e.crps_centroid_y, when, frame_dt));
    f["brier_watch_" + h].add(at_time(e.brier_watch, when, frame_dt));
    f["front_spread_m_" + h].add(at_time(e.front_spread, when, frame_dt));
  }
  f["crps_watch_arrival_s"].add(e.crps_watch_arrival);
}

// The mean at each frame over the trajectories that reach it and define it there (series hold
// NaN where a figure is undefined); NaN (written as null) where none does.
template <typename Series>  // a member pointer or a callable giving a TrajectoryScores' series
std::vector<double> mean_by_frame(const std::vector<TrajectoryScores>& scores, Series series) {
  size_t longest = 0;
  for (const auto& s : scores) longest = std::max(longest, std::invoke(series, s).size());
  std::vector<double> sum(longest, 0.0), count(longest, 0.0);
  for (const auto& s : scores) {
    const std::vector<double>& values = std::invoke(series, s);
    for (size_t k = 0; k < values.size(); ++k)
      if (std::isfinite(values[k])) {
        sum[k] += values[k];
        count[k] += 1;
      }
  }
  for (size_t k = 0; k < longest; ++k) sum[k] = count[k] > 0 ? sum[k] / count[k] : std::nan("");
  return sum;
}

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", v);
  return text;
}

std::string cell_text(const Figure& f) {
  if (f.values.empty()) return "-";
  const std::string m = number(mean(f.values));
  return f.values.size() < 2 ? m : m + " ± " + number(spread(f.values));
}

// The mean with its 90 % bootstrap interval over trajectories: "0.12 [0.08, 0.17]".
std::string interval_text(const Figure& f) {
  if (f.values.empty()) return "-";
  const std::string m = number(mean(f.values));
  if (f.values.size() < 2) return m;
  const gnn::Interval i = gnn::bootstrap_mean_interval(f.values);
  return m + " [" + number(i.low) + ", " + number(i.high) + "]";
}

// A share as a percentage with two significant digits ("0 %", "3.4 %").
std::string percent_text(double share) {
  return number(100 * share) + " %";
}

}  // namespace

namespace {

// The trajectories of the split, each with its rollout length, its spill scene and the measures
// of its recorded frames (the same for every model: measured once).
struct ComparedTrajectories {
  std::vector<gnn::Trajectory> trajectories;
  std::vector<int64_t> frames;
  std::vector<std::unique_ptr<gnn::SpillScene>> scenes;
  std::vector<FrameMeasures> recorded;
};

ComparedTrajectories read_compared(const CompareOptions& o, const gnn::DatasetMetadata& m) {
  ComparedTrajectories c;
  c.trajectories = gnn::read_split(o.data_dir, o.split, m);
  if (c.trajectories.empty())
    throw gnn::DatasetError(o.data_dir + "/" + o.split + ".h5: no trajectories");
  for (const auto& t : c.trajectories) {
    const int64_t available = t.frames() - 1 - o.from;
    if (o.from < 0 || available < 1)
      throw common::InputError("--from " + std::to_string(o.from) + ": " + t.source + " has " +
                               std::to_string(t.frames()) + " frames");
    c.frames.push_back(o.frames > 0 ? std::min<int64_t>(o.frames, available) : available);
    c.scenes.push_back(spill_scene_of(t, o.log));
    c.recorded.push_back(recorded_measures(c.scenes.back().get(), t, o.from, c.frames.back()));
  }
  return c;
}

// comparison.json's row of one model: size, FLOPs, threads, and each figure's mean and spread.
nlohmann::json model_row(const ComparedModel& model, const gnn::RuntimeSettings& mix,
                         const std::vector<TrajectoryScores>& scores,
                         const std::map<std::string, Figure>& figures, const CompareOptions& o,
                         const ComparedTrajectories& c, const gnn::DatasetMetadata& m) {
  nlohmann::json row = {{"name", model.name},
                        {"model", "sph"},
                        {"checkpoint", model.source},
                        {"params", 0},
                        {"flops_per_particle", nullptr},
                        {"threads", {{"libtorch", mix.threads}, {"blas", mix.blas_threads}}}};
  if (model.simulator) {
    gnn::LearnedSimulator& sim = *model.simulator;
    // Size of the model on the graph of the first trajectory's starting frame.
    const gnn::Trajectory& t0 = c.trajectories.front();
    const auto ids = gnn::active_ids(t0, o.from);
    const gnn::GraphInput g =
        sim.encode({gnn::position_history(t0, o.from, ids, m.frame_dt),
                    t0.oil_fraction[o.from].index_select(0, ids), t0.material, t0.boundary});
    const double flops = sim.model().flops(g.nodes(), g.edges());
    int64_t params = 0;
    for (const auto& p : sim.model().parameters()) params += p.numel();
    row["model"] = sim.model().name();
    row["params"] = params;
    if (flops >= 0 && ids.size(0) > 0) row["flops_per_particle"] = flops / double(ids.size(0));
  }
  nlohmann::json spreads = nlohmann::json::object(), intervals = nlohmann::json::object();
  for (const std::string& key : figure_order()) {
    const auto found = figures.find(key);
    const bool none = found == figures.end() || found->second.values.empty();
    row[key] = none ? nlohmann::json(nullptr) : nlohmann::json(mean(found->second.values));
    spreads[key] = none ? nlohmann::json(nullptr) : nlohmann::json(spread(found->second.values));
    if (none) {
      intervals[key] = nullptr;
    } else {
      const gnn::Interval i = gnn::bootstrap_mean_interval(found->second.values);
      intervals[key] = {i.low, i.high};
    }
  }
  row["spread"] = spreads;
  row["interval90"] = intervals;
  long skipped = 0;
  for (const auto& s : scores) skipped += s.skipped_inflow_layers;
  row["skipped_inflow_layers"] = skipped;
  double deviation = 0;
  for (const auto& s : scores) deviation = std::max(deviation, s.active_deviation_max);
  row["active_deviation_max"] = deviation;
  // Frame by frame (frame k after from_frame at index k - 1), the mean over the trajectories
  // that reach it: for figures at a simulated time rather than a frame count.
  row["by_frame"] = {
      {"rollout_mse", mean_by_frame(scores, &TrajectoryScores::mse)},
      {"oil_iou", mean_by_frame(scores, &TrajectoryScores::iou)},
      {"slick_area_error", mean_by_frame(scores, &TrajectoryScores::slick_area_error)},
      {"front_distance_error_m", mean_by_frame(scores, &TrajectoryScores::front_error)},
      {"sinkhorn_oil", mean_by_frame(scores, &TrajectoryScores::sinkhorn_oil)},
      {"sinkhorn_fluid", mean_by_frame(scores, &TrajectoryScores::sinkhorn_fluid)}};
  for (size_t j = 0; j < std::size(kFssScales); ++j)
    row["by_frame"][fss_key(j)] = mean_by_frame(
        scores, [j](const TrajectoryScores& s) -> const std::vector<double>& { return s.fss[j]; });
  return row;
}

// comparison.json's "sph": the wall time and compression of the SPH that made the data.
nlohmann::json sph_reference(const ComparedTrajectories& c, const gnn::DatasetMetadata& m,
                             std::vector<double>& sph_rates) {
  Figure sph_compression;  // the recorded frames'
  for (size_t k = 0; k < c.trajectories.size(); ++k) {
    if (!c.recorded[k].compression_mean.empty())
      sph_compression.add(mean(c.recorded[k].compression_mean));
    if (c.trajectories[k].sph_seconds_per_frame > 0)
      sph_rates.push_back(c.trajectories[k].sph_seconds_per_frame / m.frame_dt);
  }
  return {
      {"seconds_per_simulated_second",
       sph_rates.empty() ? nlohmann::json(nullptr) : nlohmann::json(mean(sph_rates))},
      {"spread", sph_rates.empty() ? nlohmann::json(nullptr) : nlohmann::json(spread(sph_rates))},
      {"compression_mean", sph_compression.values.empty()
                               ? nlohmann::json(nullptr)
                               : nlohmann::json(mean(sph_compression.values))},
      {"note", "wall time of the SPH that generated the data, as recorded in metadata.json"}};
}

const char* const kUnits =
    "each figure is the mean over the trajectories (its standard deviation under 'spread', "
    "the 90 % percentile bootstrap interval of the mean over trajectories under 'interval90'); "
    "rollout_mse_1s: squared position error (m^2) 1 s after from_frame over the particles that "
    "are the same parcel on both sides (beyond about 1 s a chaotic flow decorrelates and "
    "per-particle error scores a realistic forecast worse than a smooth one); "
    "sinkhorn_oil_H / sinkhorn_fluid_H: debiased Sinkhorn divergence (m^2, squared-distance "
    "cost, entropic epsilon = the particle diameter squared) between the predicted and recorded "
    "oil clouds (particles with oil fraction >= 1/2) / fluid clouds, H = 1 s, 2 s or the leak's "
    "end after from_frame (0 when neither side has oil; left out where one side has none); "
    "fss_Lcm_H: Fractions Skill Score of the top-view oil footprint (cells one particle "
    "diameter wide) over L cm windows at H (1 perfect, 0 no skill; left out where neither "
    "side has oil); with members > 1 every figure of a trajectory is the mean over its members; "
    "crps_front_m_H, crps_slick_area_m2_H, crps_centroid_x_m_H, crps_centroid_y_m_H: fair CRPS "
    "(Ferro 2014) of the members' leading edge, slick area and oil centroid against the "
    "recording's at H (one member: its absolute error); brier_watch_H: fair Brier score of "
    "'oil within the watch point by H', mean over watch points; crps_watch_arrival_s: fair "
    "CRPS of the first arrival at each watch point (a side that never arrived counts the "
    "rollout's length), mean over watch points; front_spread_m_H: standard deviation of the "
    "members' leading edge at H (the ensemble's own spread); "
    "one_step_mse and rollout_mse_H: squared position error (m^2) H frames after from_frame "
    "('all': mean over every rollout frame); mmd: squared maximum mean discrepancy of the "
    "fluid clouds, mean over frames; kinetic_energy_error: |KE_pred - KE_true| / KE_true, "
    "mean over frames; oil_iou_H: top-view IoU of the oil cells H frames on; "
    "slick_area_error: |A_pred - A_true| / A_true, mean over frames; front_distance_error_m: "
    "|front_pred - front_true|, mean over frames; bank_contact_time_error_s: |t_pred - "
    "t_true| of each bank's first contact (a bank touched by one side only: the time from "
    "that contact to the rollout's end), mean over banks; watch_arrival_time_error_s: the same "
    "of the first oil within each of the scene's watch points (a watch point neither side "
    "reached does not count), mean over watch points. Oil is a particle whose oil "
    "fraction is at least 1/2; slick, front and banks are spill.json's measures. "
    "compression_mean / compression_p95: mean and 95th percentile over the particles of "
    "max(rho/rho0 - 1, 0) of each predicted frame (after the relaxation when "
    "relax_iterations > 0), mean over frames; sph.compression_mean: the same of the recorded "
    "frames. by_frame: rollout_mse, oil_iou, slick_area_error, front_distance_error_m, "
    "sinkhorn_oil, sinkhorn_fluid (taken at each whole second, the leak's end and the last "
    "frame only) and fss_Lcm at "
    "every frame after from_frame (index k - 1 for frame k), mean over the trajectories that "
    "reach it and define it there (null: none does; the slick area error is undefined while "
    "the recording has no slick). "
    "seconds_per_simulated_second: wall time per frame (graph building included) over "
    "frame_dt; null: not defined for this data (e.g. no river, no bank touched). "
    "skipped_inflow_layers: standalone rollouts only, summed over the trajectories: inflow "
    "layers that could not enter because the model's reach returned too little water at the "
    "outflow (it backed up); active_deviation_max: the largest |n_pred - n_true| / n_true over "
    "the frames and trajectories, n the active fluid particles (a reach that keeps its water "
    "stays near 0). Standalone rollouts compare positions only while a particle is "
    "the same parcel on both sides (active since the same frame)";

std::string comparison_markdown(const CompareOptions& o, const gnn::DatasetMetadata& m,
                                size_t trajectories, const std::vector<ComparedModel>& models,
                                const nlohmann::json& rows,
                                std::vector<std::map<std::string, Figure>>& figures,
                                const std::vector<double>& sph_rates) {
  std::ostringstream md;
  md << "# Learned simulators compared\n\n"
     << trajectories << " trajectories of `" << o.data_dir << "` (" << o.split
     << " split), each rolled out from frame " << o.from << " (frames " << m.frame_dt
     << " s apart) on " << o.threads << " threads, "
     << (o.replay_recorded_sources
             ? "particles entering and leaving on the recording's schedule with recorded states "
               "(--replay-recorded-sources: a diagnosis, not a forecast)"
             : "standalone: the dataset's scene releases and retires particles, nothing after "
               "the first frame comes from the recording")
     << (o.relax > 0 ? ", each learned frame relaxed by " + std::to_string(o.relax) +
                           " iterations of the simulator's density correction"
                     : "")
     << "; mean ± standard deviation over trajectories. "
     << "Units and definitions: `comparison.json`, key `units`. "
     << "`comparison.png`: the first trajectory seen from above (flow down the picture), "
     << "one column per moment; the first row is the simulator (SPH), then one row per model in "
     << "the order of this table; oil drawn where a particle's oil fraction is at least 1/2."
     << (o.members > 1
             ? " `comparison_oiling.png`: the first trajectory's probability of oiling, a row per "
               "model in this order, at 1 s, 2 s, the leak's end and the last frame: each cell "
               "with oil in any member, darker the more members have oil there."
             : "")
     << "\n\n";
  md << "| model | params | one-step MSE (m²) | MSE @1 s | oil IoU "
        "@10 | oil IoU @20 | oil IoU @50 | slick area error | front error (m) | bank contact "
        "error (s) | watch-point arrival error (s) | s per frame | s per simulated s | "
        "skipped inflow layers | active particles off by (max) |\n";
  md << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (size_t k = 0; k < models.size(); ++k) {
    auto& f = figures[k];
    md << "| " << models[k].name << " (" << rows[k]["model"].get<std::string>() << ") | "
       << rows[k]["params"].get<int64_t>() << " | " << cell_text(f["one_step_mse"]) << " | "
       << cell_text(f["rollout_mse_1s"]) << " | " << cell_text(f["oil_iou_10"]) << " | "
       << cell_text(f["oil_iou_20"]) << " | " << cell_text(f["oil_iou_50"]) << " | "
       << cell_text(f["slick_area_error"]) << " | " << cell_text(f["front_distance_error_m"])
       << " | " << cell_text(f["bank_contact_time_error_s"]) << " | "
       << cell_text(f["watch_arrival_time_error_s"]) << " | " << cell_text(f["seconds_per_frame"])
       << " | " << cell_text(f["seconds_per_simulated_second"]) << " | "
       << rows[k]["skipped_inflow_layers"].get<long>() << " | "
       << percent_text(rows[k]["active_deviation_max"].get<double>()) << " |\n";
  }
  Figure sph_figure{sph_rates};
  md << "| SPH (the data) | - | - | - | - | - | - | - | - | - | - | - | " << cell_text(sph_figure)
     << " | - | - |\n";
  md << "\n## Scores a chaotic flow allows\n\n"
     << "Mean over trajectories [90 % bootstrap interval of the mean]; two models whose intervals "
     << "overlap are not told apart by these trajectories. Sinkhorn: debiased Sinkhorn divergence "
     << "of the oil (fluid) clouds, m², epsilon = particle diameter²; FSS: Fractions Skill Score "
     << "of the top-view oil footprint over the given window (1 perfect, 0 no skill); at 1 s, 2 s "
     << "and the leak's end after the start; MMD, kinetic-energy error and compression are means "
     << "over frames.\n\n";
  md << "| model | oil Sinkhorn @1 s | oil Sinkhorn @2 s | oil Sinkhorn @leak end | fluid Sinkhorn "
        "@leak end | FSS 20 cm @1 s | FSS 20 cm @2 s | FSS 20 cm @leak end | FSS 5 / 10 / 40 cm "
        "@leak end | MMD | kinetic-energy error | compression |\n";
  md << "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (size_t k = 0; k < models.size(); ++k) {
    auto& f = figures[k];
    md << "| " << models[k].name << " | " << interval_text(f["sinkhorn_oil_1s"]) << " | "
       << interval_text(f["sinkhorn_oil_2s"]) << " | " << interval_text(f["sinkhorn_oil_leak_end"])
       << " | " << interval_text(f["sinkhorn_fluid_leak_end"]) << " | "
       << interval_text(f["fss_20cm_1s"]) << " | " << interval_text(f["fss_20cm_2s"]) << " | "
       << interval_text(f["fss_20cm_leak_end"]) << " | " << cell_text(f["fss_5cm_leak_end"])
       << " / " << cell_text(f["fss_10cm_leak_end"]) << " / " << cell_text(f["fss_40cm_leak_end"])
       << " | " << interval_text(f["mmd"]) << " | " << interval_text(f["kinetic_energy_error"])
       << " | " << interval_text(f["compression_mean"]) << " |\n";
  }
  md << "\n## The ensembles as forecasts\n\n"
     << o.members << " member(s) per model and trajectory"
     << (o.members > 1
             ? ", each started from the frame jittered by up to " + number(o.member_jitter) +
                   " particle diameters with its own seed (the same seeds for every "
                   "model)"
             : " (a deterministic forecast: its CRPS is its absolute error)")
     << ". Fair CRPS (Ferro 2014) against the recording, mean over trajectories [90 % bootstrap "
     << "interval]; Brier: fair Brier score of \"oil within the watch point by then\", mean over "
     << "watch points. Lower is better.\n\n";
  md << "| model | CRPS front (m) @1 s | @2 s | @leak end | CRPS slick area (m²) @1 s | @2 s | "
        "@leak end | CRPS centroid x (m) @leak end | Brier watch points @leak end | CRPS "
        "watch-point arrival (s) | members' front spread (m) @leak end |\n";
  md << "|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (size_t k = 0; k < models.size(); ++k) {
    auto& f = figures[k];
    md << "| " << models[k].name;
    for (const char* key :
         {"crps_front_m_1s", "crps_front_m_2s", "crps_front_m_leak_end", "crps_slick_area_m2_1s",
          "crps_slick_area_m2_2s", "crps_slick_area_m2_leak_end", "crps_centroid_x_m_leak_end",
          "brier_watch_leak_end", "crps_watch_arrival_s", "front_spread_m_leak_end"})
      md << " | " << interval_text(f[key]);
    md << " |\n";
  }
  return md.str();
}

// Six moments of the first trajectory: truth, then each model.
void write_comparison_picture(const fs::path& file, const ComparedTrajectories& c,
                              const gnn::DatasetMetadata& m, int64_t from,
                              const std::vector<gnn::RolloutResult>& pictured) {
  const gnn::Trajectory& t0 = c.trajectories.front();
  const MapViewRenderer renderer(t0, m);
  std::vector<int64_t> moments;
  for (int i = 0; i < 6; ++i) moments.push_back((c.frames[0] * i + 2) / 5);
  std::vector<std::vector<common::RgbImage>> grid(1 + pictured.size());
  for (int64_t k : moments) {
    const int64_t f = std::min(k, c.frames[0]);
    grid[0].push_back(
        renderer.render(t0.position[from + f], t0.active[from + f], t0.oil_fraction[from + f]));
    for (size_t j = 0; j < pictured.size(); ++j)
      grid[1 + j].push_back(renderer.render(pictured[j].position[f], pictured[j].active[f],
                                            pictured[j].oil_fraction[f]));
  }
  common::write_png(file.string(), image_grid(grid));
}

// The first trajectory's probability of oiling, a row per model, at 1 s, 2 s, the leak's end and
// the last frame.
void write_oiling_picture(const fs::path& file, const ComparedTrajectories& c,
                          const gnn::DatasetMetadata& m,
                          const std::vector<std::vector<gnn::RolloutResult>>& ensembles) {
  const MapViewRenderer renderer(c.trajectories.front(), m);
  const int64_t frames = c.frames[0];
  std::vector<int64_t> moments;
  for (double seconds : {1.0, 2.0}) moments.push_back(frame_at(seconds, m.frame_dt));
  if (const gnn::SpillScene* scene = c.scenes[0].get())
    if (const auto end = scene->leak_end_time())
      moments.push_back(frame_at(
          *end - c.trajectories[0].time[ensembles[0][0].first_frame].item<double>(), m.frame_dt));
  moments.push_back(frames);
  std::vector<std::vector<common::RgbImage>> grid;
  for (const auto& members : ensembles) {
    grid.emplace_back();
    for (int64_t k : moments)
      grid.back().push_back(renderer.render_oiling(members, std::clamp<int64_t>(k, 1, frames),
                                                   2 * m.particle_radius));
  }
  common::write_png(file.string(), image_grid(grid));
}

// Refuses option combinations that would compare unlike with unlike.
void check_compare_options(const CompareOptions& o) {
  if (o.checkpoints.empty() && !o.constant_velocity && !(o.ceiling_jitter > 0))
    throw common::InputError("compare: give --checkpoints, --constant-velocity or --ceiling");
  if (o.members > 1 && o.replay_recorded_sources)
    throw common::InputError(
        "compare: --members runs jittered members standalone; it has no "
        "--replay-recorded-sources");
  if (o.ceiling_jitter > 0 && o.replay_recorded_sources)
    throw common::InputError(
        "compare: --ceiling runs the scene's own sources; it has no --replay-recorded-sources");
}

// Member j of trajectory k, rolled out by `model` (a learned simulator, or the dataset's own
// solver for the ceiling) and scored; its frames are left in `kept`.
TrajectoryScores run_member(ComparedModel& model, const ComparedTrajectories& c,
                            const gnn::DatasetMetadata& m, const CompareOptions& o, size_t k, int j,
                            Sources sources, gnn::RolloutResult& kept) {
  const auto on_frame = [&](int64_t frame) {
    common::throw_if_stopped(o.stop, [&] {
      return "at frame " + std::to_string(frame) + " of " + model.name + " on " +
             c.trajectories[k].source + "; nothing written";
    });
  };
  const double member_jitter = o.member_jitter * 2 * m.particle_radius;  // m
  // The ceiling's first member keeps its seed of one-run comparisons; every model's member j
  // starts from the same jittered positions.
  const uint64_t seed = uint64_t(k + 1) + 1000 * uint64_t(j);
  const gnn::Trajectory& t = c.trajectories[k];
  if (!model.simulator) {
    const double jitter = o.members > 1 ? member_jitter : o.ceiling_jitter * 2 * m.particle_radius;
    kept = gnn::solver_rollout(t, o.from, c.frames[k], m.frame_dt, jitter, seed, on_frame);
    return score_frames(kept, t, m, c.scenes[k].get(), c.recorded[k], o.from, c.frames[k]);
  }
  const double jitter = o.members > 1 ? member_jitter : 0.0;
  if (j == 0)
    return score_rollout(*model.simulator, t, m, c.scenes[k].get(), c.recorded[k], o.from,
                         c.frames[k], sources, o.relax, k == 0 ? &kept : nullptr, on_frame, jitter,
                         seed);
  // The one-step error is the same for every member: taken once, by member 0.
  kept = roll_out(*model.simulator, t, o.from, c.frames[k], m.frame_dt, sources, on_frame,
                  relaxation_hook(c.scenes[k].get(), o.relax), jitter, seed);
  return score_frames(kept, t, m, c.scenes[k].get(), c.recorded[k], o.from, c.frames[k]);
}

// comparison.json's content.
nlohmann::json comparison_json(const CompareOptions& o, const gnn::DatasetMetadata& m,
                               const ComparedTrajectories& c, Sources sources,
                               const nlohmann::json& rows, const nlohmann::json& sph) {
  nlohmann::json trajectories = nlohmann::json::array();
  for (size_t k = 0; k < c.trajectories.size(); ++k)
    trajectories.push_back({{"source", c.trajectories[k].source}, {"frames", c.frames[k]}});
  return {{"data", o.data_dir},
          {"split", o.split},
          {"from_frame", o.from},
          {"frame_dt", m.frame_dt},
          {"threads", o.threads},
          {"relax_iterations", o.relax},
          {"members", o.members},
          {"member_jitter_diameters",
           o.members > 1 ? nlohmann::json(o.member_jitter) : nlohmann::json(nullptr)},
          {"sources", sources_name(sources)},
          {"units", kUnits},
          {"models", rows},
          {"sph", sph},
          {"trajectories", trajectories}};
}

}  // namespace

void run_compare(const CompareOptions& o) {
  check_compare_options(o);
  const Sources rollout_sources = sources_of(o.replay_recorded_sources);
  common::OutputFolderPolicy policy;
  policy.markers = {"comparison.json", "comparison.md"};  // teacher_student.md: optional
  policy.replace = true;
  policy.inputs = {o.data_dir};
  for (const auto& c : o.checkpoints) policy.inputs.emplace_back(c);
  policy.log = o.log;
  common::OutputFolder output(o.out_dir, policy);

  const gnn::DatasetMetadata m =
      gnn::read_metadata((fs::path(o.data_dir) / "metadata.json").string());
  std::vector<ComparedModel> models = load_models(o, m);
  const ComparedTrajectories c = read_compared(o, m);

  std::unique_ptr<common::ProgressReporter> progress;
  if (o.log)
    progress = std::make_unique<common::ProgressReporter>(
        *o.log, false, long(models.size() * c.trajectories.size()) * o.members, "compare");
  nlohmann::json rows = nlohmann::json::array();
  std::vector<std::map<std::string, Figure>> figures;
  std::vector<gnn::RolloutResult> pictured;  // each model's first member of the first trajectory
  // With members: every member of the first trajectory, per model (the probability of oiling).
  std::vector<std::vector<gnn::RolloutResult>> ensembles;
  long done = 0;
  for (auto& model : models) {
    const gnn::RuntimeSettings mix =
        o.blas_threads > 0 || !model.simulator
            ? gnn::RuntimeSettings{o.threads, std::max(o.blas_threads, 1)}
            : gnn::inference_runtime(o.threads,
                                     model.simulator->model().infers_on_one_blas_thread());
    gnn::configure_runtime(mix);
    std::vector<TrajectoryScores> scores;  // every member of every trajectory
    std::map<std::string, Figure> model_figures;
    for (size_t k = 0; k < c.trajectories.size(); ++k) {
      std::vector<TrajectoryScores> members;
      for (int j = 0; j < o.members; ++j) {
        gnn::RolloutResult kept;
        members.push_back(run_member(model, c, m, o, k, j, rollout_sources, kept));
        if (k == 0 && o.members > 1) {
          if (j == 0) ensembles.emplace_back();
          ensembles.back().push_back(kept);  // shares the tensors
        }
        if (k == 0 && j == 0) pictured.push_back(std::move(kept));
        if (progress)
          progress->update(++done, model.name + " " + c.trajectories[k].source +
                                       (o.members > 1 ? " member " + std::to_string(j + 1) : ""));
      }
      add_trajectory_figures(model_figures, members, m.frame_dt);
      scores.insert(scores.end(), members.begin(), members.end());
    }
    figures.push_back(std::move(model_figures));
    rows.push_back(model_row(model, mix, scores, figures.back(), o, c, m));
  }
  if (progress) progress->finish("");

  std::vector<double> sph_rates;
  const nlohmann::json sph = sph_reference(c, m, sph_rates);
  const nlohmann::json result = comparison_json(o, m, c, rollout_sources, rows, sph);
  const fs::path out = output.staging();
  common::write_file_atomically((out / "comparison.json").string(), result.dump(2) + "\n");
  common::write_file_atomically(
      (out / "comparison.md").string(),
      comparison_markdown(o, m, c.trajectories.size(), models, rows, figures, sph_rates));
  const std::string table6 = teacher_student_table(result);
  if (!table6.empty()) common::write_file_atomically((out / "teacher_student.md").string(), table6);
  write_comparison_picture(out / "comparison.png", c, m, o.from, pictured);
  if (o.members > 1) write_oiling_picture(out / "comparison_oiling.png", c, m, ensembles);
  write_compare_report(out);
  output.commit();
  if (o.log)
    *o.log << models.size() << " models compared on " << c.trajectories.size()
           << " trajectories; written to " << output.target().string() << "\n";
}

}  // namespace infer
