#pragma once
// How well one rollout of a learned simulator matches the recording it replays, frame by frame:
// what `spill-infer eval` and `compare` report. Position error, MMD, kinetic energy and the oil
// footprint's IoU, and the responder's measures (slick area, front distance, first bank contact)
// computed for the truth and the prediction with the simulator's own spill.json code
// (gnn/eval/spill_measures.h).

#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <vector>

#include "gnn/data/dataset.h"
#include "gnn/eval/rollout.h"
#include "gnn/eval/spill_measures.h"
#include "gnn/models/learned_simulator.h"

namespace infer {

// What spill.json's code and the density measure say of one side's frames 1..F (empty without
// the dataset's scene): slick area (m^2); for rivers the leading edge downstream of the leak (m)
// and the first time (s after the rollout's start) each bank (left, right) was touched, if it
// was; the first time oil reached each of the scene's watch points, if it did (by name, every
// watch point present); the compression max(rho/rho0 - 1, 0), mean and 95th percentile over the
// particles; the oil's centroid.
struct FrameMeasures {
  std::vector<double> slick_area, front;
  std::vector<double> centroid_x, centroid_y;  // the oil's mean top-view position (m); NaN: none
  std::optional<double> bank[2];
  std::map<std::string, std::optional<double>> arrival;
  std::vector<double> compression_mean, compression_p95;
};

// The recording's measures over frames from+1 .. from+frames of `t`: the same for every model, so
// taken once per trajectory and handed to score_rollout.
FrameMeasures recorded_measures(gnn::SpillScene* scene, const gnn::Trajectory& t, int64_t from,
                                int64_t frames);

struct TrajectoryScores {
  std::optional<double> one_step_mse;           // none for the ceiling (no model to take one step)
  std::vector<double> mse, mmd, ke_error, iou;  // per rollout frame 1..F
  // Per rollout frame 1..F, NaN where undefined: |A_pred - A_true| / A_true (undefined without
  // a recorded slick) and |front_pred - front_true| (m; undefined without a river).
  std::vector<double> slick_area_error, front_error;
  FrameMeasures recorded, predicted;  // spill and density measures of each side
  double rollout_seconds = 0;         // simulated seconds the rollout spans
  double wall_s_per_frame = 0, sph_seconds_per_frame = 0;
  long skipped_inflow_layers = 0;  // gnn::RolloutResult's
  // The largest |n_pred - n_true| / n_true over frames 1..F, n the active fluid particles: a
  // forecast that keeps the river's water stays near 0 (a draining reach does not).
  double active_deviation_max = 0;
  // Scores a chaotic flow allows (issue 48), per rollout frame 1..F, NaN where not taken: the
  // debiased Sinkhorn divergence (m^2, epsilon kSinkhornBlurDiameters^2 particle diameters
  // squared) of the oil clouds and of the fluid clouds, at the frames of costly_frames() only
  // (each costs O(n^2)); the Fractions Skill Score of the oil footprint at each of kFssScales,
  // every frame (NaN while neither side has oil).
  std::vector<double> sinkhorn_oil, sinkhorn_fluid;
  std::vector<std::vector<double>> fss;  // [scale][frame]
  std::optional<double> leak_end;        // s after the rollout's start the leak ends, if within it
};

// The neighbourhoods (m) the oil footprint's Fractions Skill Score is taken at, on a grid of one
// particle diameter (a window of round(scale / diameter) cells, at least one).
inline constexpr double kFssScales[] = {0.05, 0.10, 0.20, 0.40};
// The Sinkhorn divergence's blur, in particle diameters: epsilon = (blur x diameter)^2.
inline constexpr double kSinkhornBlurDiameters = 1.0;

// The rollout frame (1-based) `seconds` after its start, round(seconds / frame_dt).
int64_t frame_at(double seconds, double frame_dt);
// The frames where the costly scores are taken: each whole second after the start, the leak's
// end (when given) and the last frame.
std::vector<int64_t> costly_frames(int64_t frames, double frame_dt,
                                   const std::optional<double>& leak_end);

// How a rollout gets the particles that enter and leave.
enum class Sources {
  kScene,     // standalone: the scene's own emitters, inflow and sinks (gnn/eval/scene_rollout.h)
  kRecorded,  // diagnosis: launched and retired on the recording's schedule, with recorded
              // states (gnn/eval/rollout.h; --replay-recorded-sources)
};
const char* sources_name(Sources sources);
inline Sources sources_of(bool replay_recorded_sources) {
  return replay_recorded_sources ? Sources::kRecorded : Sources::kScene;
}

// Rolls `simulator` out over frames from+1 .. from+frames of `t` (its starting positions jittered
// by up to `jitter` m with `seed`, standalone only) and scores it against the
// recording, whose measures `recorded` are recorded_measures(scene, t, from, frames); `scene`
// (may be null) gives the particle volume and the river for the oil measures and the density
// correction: with `relax_iterations` > 0 every learned frame gets that many iterations of it
// (gnn/eval/spill_measures.h, sph/simulation/density_relaxation.h). `kept` receives the rollout
// when given.
//
// Position and kinetic-energy errors compare a particle on both sides only while it is the same
// particle on both: active, and active since the same frame (a standalone rollout recycles
// inflow water in its own order, so an identity that re-entered is another parcel of water).
// Cloud distances and oil footprints compare each side's own active particles.
TrajectoryScores score_rollout(gnn::LearnedSimulator& simulator, const gnn::Trajectory& t,
                               const gnn::DatasetMetadata& m, gnn::SpillScene* scene,
                               const FrameMeasures& recorded, int64_t from, int64_t frames,
                               Sources sources, int relax_iterations = 0,
                               gnn::RolloutResult* kept = nullptr,
                               const std::function<void(int64_t)>& on_frame = {}, double jitter = 0,
                               uint64_t seed = 0);

// Scores a rollout `r` of frames from+1 .. from+frames of `t` as score_rollout does (its
// one_step_mse left empty).
TrajectoryScores score_frames(gnn::RolloutResult& r, const gnn::Trajectory& t,
                              const gnn::DatasetMetadata& m, gnn::SpillScene* scene,
                              const FrameMeasures& recorded, int64_t from, int64_t frames);

// Rolls out as `sources` says (arguments as gnn::rollout's; `jitter` (m) and `seed` as
// gnn::standalone_rollout's, standalone only: common::InputError for a replayed one).
gnn::RolloutResult roll_out(gnn::LearnedSimulator& simulator, const gnn::Trajectory& t,
                            int64_t from, int64_t frames, double frame_dt, Sources sources,
                            const std::function<void(int64_t)>& on_frame,
                            const gnn::FrameCorrection& correct, double jitter = 0,
                            uint64_t seed = 0);

// [F + 1, N] int64: the frame (0 ..) at which each particle's present run of active frames
// began, -1 where it is inactive.
torch::Tensor active_since(const torch::Tensor& active);

// The hook that relaxes each learned frame by `iterations` of the scene's density correction;
// empty for 0. Throws common::InputError when iterations > 0 and there is no scene.
gnn::FrameCorrection relaxation_hook(gnn::SpillScene* scene, int iterations);

// Responder figures of one trajectory's scores (absent when it has none of that kind):
// mean |A_pred - A_true| / A_true over frames with a slick; mean |front_pred - front_true| (m);
// mean over banks of |t_pred - t_true| (s), a bank touched by one side only counting the time
// from that contact to the end of the rollout (a lower bound of the error); the same over the
// watch points' arrival times (a watch point neither side reached does not count).
std::optional<double> slick_area_error(const TrajectoryScores& s);
std::optional<double> front_distance_error(const TrajectoryScores& s);
std::optional<double> bank_contact_time_error(const TrajectoryScores& s);
std::optional<double> watch_arrival_time_error(const TrajectoryScores& s);

// The trajectory's scene for the oil measures; null, with a line on `log` saying why the
// responder measures are left out, when the dataset carries no scene the simulator accepts.
std::unique_ptr<gnn::SpillScene> spill_scene_of(const gnn::Trajectory& t, std::ostream* log);

double mean(const std::vector<double>& values);
double spread(const std::vector<double>& values);  // standard deviation, 0 for fewer than 2

}  // namespace infer
