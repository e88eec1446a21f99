#pragma once
// A learned simulator run as a simulator of a scene: it moves the particles of an
// sph::Simulation frame by frame while the scene's own sources and sinks act between its frames
// (the emitters and the river's inflow release particles on the scene's schedule; the outflow,
// the terrain's edges and the domain retire them: Simulation::release_sources and
// apply_external_frame). Nothing is read from a recording. `spill-infer predict` runs a scene this
// way from its start or a saved state; eval and compare run each test trajectory this way from a
// recorded frame (standalone_rollout).
//
// A particle's input history is its own last 6 positions; one that has just been released (or
// was active when the run began without a recorded history) gets the launched history of
// training, stepped back along its velocity (gnn/data/frame_window.h).

#include <torch/torch.h>

#include <functional>
#include <memory>
#include <string>

#include "gnn/data/dataset.h"
#include "gnn/eval/rollout.h"
#include "gnn/models/learned_simulator.h"
#include "sph/simulation/simulation.h"

namespace gnn {

class SceneRollout {
 public:
  // `material`: the material rows (Trajectory::material) of the scene's materials; `where`
  // names the run in errors (the scene file, or the trajectory).
  SceneRollout(LearnedSimulator& model, sph::Simulation& simulation, torch::Tensor material,
               double frame_dt, std::string where);

  // Histories [n, 6, 3] (oldest first) of the particles `ids` [n] (int64), active now.
  void set_history(const torch::Tensor& ids, const torch::Tensor& history);
  // One frame: the model's prediction (then `correct`, as rollout()'s), the sinks, then the
  // sources due by the frame's end (on the first frame, also those due by its start). `frame`
  // names the frame in errors. Throws std::runtime_error when the model's positions are not
  // finite.
  sph::ExternalFrameStats advance(int frame, const FrameCorrection& correct = {});
  // Particles the frames so far retired by the river's rules, and outside the domain.
  const sph::ExternalFrameStats& retired() const { return retired_; }
  // Before the first frame: one member of an ensemble. Releases what is due, then moves the
  // input history of every active particle by its own uniform offset in [-jitter, jitter] m per
  // coordinate (drawn as jitter_active_positions draws them, so the model starts from a
  // displaced state with its velocities unchanged). Throws std::logic_error after a frame.
  void jitter_start(double jitter, uint64_t seed);

 private:
  // Gives the active particles `ids` (at `position`, `velocity`) that have no history of their
  // own the launched history of training.
  void launch_fresh(const torch::Tensor& ids, const torch::Tensor& position,
                    const torch::Tensor& velocity);

  LearnedSimulator& model_;
  sph::Simulation& sim_;
  torch::Tensor material_, boundary_;
  std::string where_;
  double frame_dt_, start_time_;
  int64_t frames_ = 0;
  torch::Tensor history_;  // [N, 6, 3] by particle id
  torch::Tensor current_;  // [N] bool: the history of the particle is its own, up to now
  sph::ExternalFrameStats retired_;
};

// The simulation's particles in identity order: position [N, 3] float32, active [N] bool,
// oil fraction [N] float32.
struct IdentityFrame {
  torch::Tensor position, active, oil_fraction;
};
IdentityFrame identity_frame(const sph::Simulation& simulation);

// The trajectory's scene (t.scene) continued from its recorded frame `frame`
// (Simulation::restore_recorded_frame), the frame first passed through `adjust` when given.
// Throws DatasetError when the trajectory carries no scene or its scene does not have the
// trajectory's particles.
std::unique_ptr<sph::Simulation> simulation_at_frame(
    const Trajectory& t, int64_t frame, double frame_dt,
    const std::function<void(sph::RecordedFrame&)>& adjust = {});

// What a rollout restarted from a recorded frame shares, whoever moves the particles (the model
// or the dataset's solver): the trajectory's scene restored at `first_frame` (its active
// particles jittered as jitter_active_positions does, returning the offsets in `offset`), and a
// result that starts with the recorded frame. Throws std::invalid_argument naming the trajectory
// when the frames are not in it.
struct RestartedRollout {
  std::unique_ptr<sph::Simulation> simulation;
  torch::Tensor offset;  // [N, 3] each particle's start offset (zero for inactive ones)
  RolloutResult result;  // frame 0 the recording's; frames + 1 rows
};
RestartedRollout restart_rollout(const Trajectory& t, int64_t first_frame, int64_t frames,
                                 double frame_dt, double jitter, uint64_t seed);
// Runs frames 1..frames of `rollout`: `advance(k)` moves its simulation to frame k, after which
// the frame's identity-ordered state and its wall time are recorded and `on_frame(k)` is called.
void record_frames(RestartedRollout& rollout, const std::function<void(int64_t)>& advance,
                   const std::function<void(int64_t)>& on_frame);

// Rolls `model` out from recorded frame `first_frame` of `t` for `frames` frames, standalone:
// the state and history of that frame are the recording's, everything after comes from the model
// and from the sources and sinks of the trajectory's scene (t.scene). Inactive rows of the
// result keep a particle's last position. Throws DatasetError when the trajectory carries no
// scene or its scene does not have the trajectory's particles; arguments as rollout()'s.
// With `jitter` > 0 the active particles start moved by independent uniform offsets in
// [-jitter, jitter] m per coordinate (seeded by `seed`), each particle's whole input history by
// its own offset (its velocity unchanged): one member of an ensemble, as jittered_frame makes the
// solver's.
RolloutResult standalone_rollout(LearnedSimulator& model, const Trajectory& t, int64_t first_frame,
                                 int64_t frames, double frame_dt,
                                 const std::function<void(int64_t)>& on_frame = {},
                                 const FrameCorrection& correct = {}, double jitter = 0,
                                 uint64_t seed = 0);

// Moves the active particles of `f` by independent uniform offsets in [-jitter, jitter] m per
// coordinate drawn in particle order from a generator seeded by `seed`; returns each particle's
// offset [N, 3] (zero for inactive ones). Throws std::invalid_argument for a negative jitter.
torch::Tensor jitter_active_positions(sph::RecordedFrame& f, double jitter, uint64_t seed);
// The offsets jitter_active_positions draws for particles flagged in `active` (one per particle
// id, in id order), zero elsewhere: [N, 3] float32.
torch::Tensor jitter_offsets(const std::vector<std::uint8_t>& active, double jitter, uint64_t seed);

}  // namespace gnn
