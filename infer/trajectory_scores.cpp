#include "infer/trajectory_scores.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <set>

#include "common/exit_codes.h"
#include "gnn/data/frame_window.h"
#include "gnn/eval/fractions_skill.h"
#include "gnn/eval/metrics.h"
#include "gnn/eval/scene_rollout.h"
#include "gnn/eval/sinkhorn.h"
#include "sph/river/slick_shape.h"

namespace infer {

namespace {

// Velocities (m/s) between frames k-1 and k of particles active in both.
torch::Tensor frame_velocity(const torch::Tensor& position, const torch::Tensor& active, int64_t k,
                             double dt, torch::Tensor& both) {
  both = active[k] & active[k - 1];
  return (position[k] - position[k - 1]) / dt;
}

// The measures of frames 1..F of one side (truth or prediction); frame 0 starts the river's
// bank record.
FrameMeasures measure_frames(gnn::SpillScene& scene, const torch::Tensor& position,
                             const torch::Tensor& active, const torch::Tensor& fraction,
                             const torch::Tensor& time) {
  FrameMeasures out;
  auto river = scene.river_metrics();
  sph::DensityRelaxation& density = scene.relaxation();
  const double t0 = time[0].item<double>();
  for (int64_t k = 0; k < position.size(0); ++k) {
    const sph::FluidParticles fluid =
        gnn::fluid_of_frame(position[k], active[k], fraction[k], scene.particle_volume());
    const double t = time[k].item<double>() - t0;
    if (river) {
      const sph::SpillFrame& f = river->measure(fluid, t, 0.0);
      if (f.left_bank_m > 0 && !out.bank[0]) out.bank[0] = t;
      if (f.right_bank_m > 0 && !out.bank[1]) out.bank[1] = t;
      if (k > 0) {
        out.slick_area.push_back(f.slick_area_m2);
        out.front.push_back(f.front_distance_m);
      }
    } else if (k > 0) {
      out.slick_area.push_back(sph::measure_slick(fluid, sph::Real(scene.cell())).area_m2);
    }
    if (k > 0) {
      const auto oil = position[k].index({active[k] & (fraction[k] >= gnn::kOilFractionThreshold)});
      const bool none = oil.size(0) == 0;
      const auto centre = none ? torch::Tensor() : oil.to(torch::kFloat64).mean(0);
      out.centroid_x.push_back(none ? std::nan("") : centre[0].item<double>());
      out.centroid_y.push_back(none ? std::nan("") : centre[1].item<double>());
      // fluid_of_frame holds the active particles only.
      const sph::CompressionStats c = density.measure(fluid.position, fluid.oil_fraction);
      out.compression_mean.push_back(c.mean);
      out.compression_p95.push_back(c.p95);
    }
  }
  if (river)
    for (const std::string& name : scene.watch_point_names())
      out.arrival[name] = river->arrival(name);
  return out;
}

// The mean over the finite values; none when there are none.
std::optional<double> finite_mean(const std::vector<double>& values) {
  std::vector<double> finite;
  for (double v : values)
    if (std::isfinite(v)) finite.push_back(v);
  if (finite.empty()) return std::nullopt;
  return mean(finite);
}

// |t_pred - t_true| of an event each side may or may not have seen within a rollout of
// `seconds`: seen by one side only, the time from that sighting to the rollout's end (a lower
// bound of the error); seen by neither, none.
std::optional<double> event_time_error(const std::optional<double>& truth,
                                       const std::optional<double>& predicted, double seconds) {
  if (truth && predicted) return std::abs(*predicted - *truth);
  if (truth || predicted) return seconds - (truth ? *truth : *predicted);
  return std::nullopt;
}

}  // namespace

FrameMeasures recorded_measures(gnn::SpillScene* scene, const gnn::Trajectory& t, int64_t from,
                                int64_t frames) {
  if (!scene) return {};
  const auto span = [&](const torch::Tensor& x) { return x.slice(0, from, from + frames + 1); };
  return measure_frames(*scene, span(t.position), span(t.active), span(t.oil_fraction),
                        span(t.time));
}

TrajectoryScores score_rollout(gnn::LearnedSimulator& sim, const gnn::Trajectory& t,
                               const gnn::DatasetMetadata& m, gnn::SpillScene* scene,
                               const FrameMeasures& recorded, int64_t from, int64_t frames,
                               Sources sources, int relax_iterations, gnn::RolloutResult* kept,
                               const std::function<void(int64_t)>& on_frame, double jitter,
                               uint64_t seed) {
  std::vector<int64_t> one_step_frames;
  const int64_t first = gnn::kWindow - 1, last = t.frames() - 2;
  const int64_t stride = std::max<int64_t>(1, (last - first + 1) / 20);
  for (int64_t f = first; f <= last; f += stride) one_step_frames.push_back(f);
  const double one_step_mse = gnn::one_step_position_mse(sim, t, one_step_frames, m.frame_dt);

  auto r = roll_out(sim, t, from, frames, m.frame_dt, sources, on_frame,
                    relaxation_hook(scene, relax_iterations), jitter, seed);
  TrajectoryScores s = score_frames(r, t, m, scene, recorded, from, frames);
  s.one_step_mse = one_step_mse;
  if (kept) *kept = std::move(r);
  return s;
}

TrajectoryScores score_frames(gnn::RolloutResult& r, const gnn::Trajectory& t,
                              const gnn::DatasetMetadata& m, gnn::SpillScene* scene,
                              const FrameMeasures& recorded, int64_t from, int64_t frames) {
  TrajectoryScores s;
  auto truth = t.position.slice(0, from, from + frames + 1);
  auto truth_active = t.active.slice(0, from, from + frames + 1);
  auto truth_fraction = t.oil_fraction.slice(0, from, from + frames + 1);
  const double cell = 2 * m.particle_radius;
  // Oil is what each side's oil fraction says at that frame (spill.json's rule), not the type a
  // particle was emitted as: the simulator moves oil between particles, and so does the model.
  const auto truth_oil = truth_fraction >= gnn::kOilFractionThreshold;
  const auto predicted_oil = r.oil_fraction >= gnn::kOilFractionThreshold;
  const auto predicted_since = active_since(r.active), truth_since = active_since(truth_active);
  const auto time = t.time.slice(0, from, from + frames + 1);
  s.rollout_seconds = (time[frames] - time[0]).item<double>();
  if (scene)
    if (const auto end = scene->leak_end_time()) {
      const double after_start = *end - time[0].item<double>();
      if (after_start > 0 && after_start <= s.rollout_seconds + 1e-9) s.leak_end = after_start;
    }
  const auto costly = costly_frames(frames, m.frame_dt, s.leak_end);
  const std::set<int64_t> costly_set(costly.begin(), costly.end());
  gnn::SinkhornSettings sinkhorn;
  sinkhorn.epsilon = std::pow(kSinkhornBlurDiameters * cell, 2);
  s.fss.assign(std::size(kFssScales), {});
  for (int64_t k = 1; k <= frames; ++k) {
    // The same particle on both sides: active on both, since the same frame.
    auto same = r.active[k] & truth_active[k] & (predicted_since[k] == truth_since[k]);
    s.mse.push_back(gnn::position_mse(r.position[k], truth[k], same));
    s.mmd.push_back(gnn::mmd_rbf(r.position[k].index({r.active[k]}),
                                 truth[k].index({truth_active[k]}), m.connectivity_radius));
    torch::Tensor both_p, both_t;
    auto vp = frame_velocity(r.position, r.active, k, m.frame_dt, both_p);
    auto vt = frame_velocity(truth, truth_active, k, m.frame_dt, both_t);
    const auto moving = same & both_p & both_t;
    const double ke_p = gnn::mean_kinetic_energy(vp, moving);
    const double ke_t = gnn::mean_kinetic_energy(vt, moving);
    s.ke_error.push_back(ke_t > 0 ? std::abs(ke_p - ke_t) / ke_t : 0.0);
    s.iou.push_back(
        gnn::top_view_iou(r.position[k].index({r.active[k] & predicted_oil[k]}).slice(1, 0, 2),
                          truth[k].index({truth_active[k] & truth_oil[k]}).slice(1, 0, 2), cell));
    const auto oil_p = r.position[k].index({r.active[k] & predicted_oil[k]});
    const auto oil_t = truth[k].index({truth_active[k] & truth_oil[k]});
    for (size_t j = 0; j < std::size(kFssScales); ++j)
      s.fss[j].push_back(
          gnn::fractions_skill_score(oil_p.slice(1, 0, 2), oil_t.slice(1, 0, 2), cell,
                                     std::max<int64_t>(1, std::llround(kFssScales[j] / cell))));
    const bool take = costly_set.count(k) > 0;
    s.sinkhorn_oil.push_back(take ? gnn::sinkhorn_divergence(oil_p, oil_t, sinkhorn)
                                  : std::nan(""));
    s.sinkhorn_fluid.push_back(take ? gnn::sinkhorn_divergence(r.position[k].index({r.active[k]}),
                                                               truth[k].index({truth_active[k]}),
                                                               sinkhorn)
                                    : std::nan(""));
    const double n_true = truth_active[k].sum().item<double>();
    if (n_true > 0)
      s.active_deviation_max = std::max(
          s.active_deviation_max, std::abs(r.active[k].sum().item<double>() - n_true) / n_true);
  }
  s.recorded = recorded;
  if (scene) s.predicted = measure_frames(*scene, r.position, r.active, r.oil_fraction, time);
  const double undefined = std::nan("");
  for (int64_t k = 0; k < frames; ++k) {
    const auto at = [&](const std::vector<double>& v) {
      return size_t(k) < v.size() ? v[k] : undefined;
    };
    const double area = at(recorded.slick_area), front = at(recorded.front);
    s.slick_area_error.push_back(area > 0 ? std::abs(at(s.predicted.slick_area) - area) / area
                                          : undefined);
    s.front_error.push_back(std::abs(at(s.predicted.front) - front));
  }
  s.wall_s_per_frame =
      std::accumulate(r.frame_seconds.begin(), r.frame_seconds.end(), 0.0) / double(frames);
  s.sph_seconds_per_frame = t.sph_seconds_per_frame;
  s.skipped_inflow_layers = r.skipped_inflow_layers;
  return s;
}

int64_t frame_at(double seconds, double frame_dt) {
  return int64_t(std::llround(seconds / frame_dt));
}

std::vector<int64_t> costly_frames(int64_t frames, double frame_dt,
                                   const std::optional<double>& leak_end) {
  std::set<int64_t> at{frames};
  for (int second = 1; frame_at(second, frame_dt) <= frames; ++second)
    at.insert(frame_at(second, frame_dt));
  if (leak_end) at.insert(std::clamp<int64_t>(frame_at(*leak_end, frame_dt), 1, frames));
  return {at.begin(), at.end()};
}

const char* sources_name(Sources sources) {
  return sources == Sources::kScene ? "standalone" : "replayed recording";
}

gnn::RolloutResult roll_out(gnn::LearnedSimulator& simulator, const gnn::Trajectory& t,
                            int64_t from, int64_t frames, double frame_dt, Sources sources,
                            const std::function<void(int64_t)>& on_frame,
                            const gnn::FrameCorrection& correct, double jitter, uint64_t seed) {
  if (sources == Sources::kRecorded) {
    if (jitter > 0)
      throw common::InputError(
          "--replay-recorded-sources replays the recording: it has no jittered members");
    return gnn::rollout(simulator, t, from, frames, frame_dt, on_frame, correct);
  }
  return gnn::standalone_rollout(simulator, t, from, frames, frame_dt, on_frame, correct, jitter,
                                 seed);
}

torch::Tensor active_since(const torch::Tensor& active) {
  auto since = torch::full(active.sizes(), -1, torch::kInt64);
  since[0].masked_fill_(active[0], 0);
  for (int64_t k = 1; k < active.size(0); ++k) {
    auto started = active[k] & ~active[k - 1];
    since[k] = torch::where(started, torch::full_like(since[k], k), since[k - 1]);
    since[k].masked_fill_(~active[k], -1);
  }
  return since;
}

std::optional<double> slick_area_error(const TrajectoryScores& s) {
  return finite_mean(s.slick_area_error);
}

std::optional<double> front_distance_error(const TrajectoryScores& s) {
  return finite_mean(s.front_error);
}

std::optional<double> bank_contact_time_error(const TrajectoryScores& s) {
  std::vector<double> errors;
  for (int b = 0; b < 2; ++b)
    if (auto e = event_time_error(s.recorded.bank[b], s.predicted.bank[b], s.rollout_seconds))
      errors.push_back(*e);
  if (errors.empty()) return std::nullopt;
  return mean(errors);
}

std::optional<double> watch_arrival_time_error(const TrajectoryScores& s) {
  std::vector<double> errors;
  for (const auto& [name, truth] : s.recorded.arrival) {
    const auto found = s.predicted.arrival.find(name);
    const std::optional<double> predicted =
        found == s.predicted.arrival.end() ? std::nullopt : found->second;
    if (auto e = event_time_error(truth, predicted, s.rollout_seconds)) errors.push_back(*e);
  }
  if (errors.empty()) return std::nullopt;
  return mean(errors);
}

gnn::FrameCorrection relaxation_hook(gnn::SpillScene* scene, int iterations) {
  if (iterations <= 0) return {};
  if (!scene)
    throw common::InputError("--relax " + std::to_string(iterations) +
                             ": the dataset carries no scene the simulator accepts, so there is "
                             "no density correction to relax with");
  // The scene owns its relaxation and outlives the rollout: the hook holds it without owning it.
  return gnn::relaxation_correction(
      std::shared_ptr<sph::DensityRelaxation>(std::shared_ptr<void>(), &scene->relaxation()),
      iterations);
}

std::unique_ptr<gnn::SpillScene> spill_scene_of(const gnn::Trajectory& t, std::ostream* log) {
  try {
    return std::make_unique<gnn::SpillScene>(t);
  } catch (const std::exception& e) {
    if (log)
      *log << "note: slick area, front and bank measures left out for " << t.source << ": "
           << e.what() << "\n";
    return nullptr;
  }
}

double mean(const std::vector<double>& v) {
  return v.empty() ? 0.0 : std::accumulate(v.begin(), v.end(), 0.0) / double(v.size());
}

double spread(const std::vector<double>& v) {
  if (v.size() < 2) return 0.0;
  const double m = mean(v);
  double sum = 0;
  for (double x : v) sum += (x - m) * (x - m);
  return std::sqrt(sum / double(v.size() - 1));
}

}  // namespace infer
