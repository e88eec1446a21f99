#pragma once
// Rolls a learned simulator forward from a recorded frame. Particles emitted by the leak or
// recycled at the inflow are activated, and particles leaving through the outflow retired, on the
// recorded schedule: these are boundary conditions, not predictions. A particle activated at
// frame t enters at its recorded position and velocity (its history extrapolated back along the
// velocity, as in training) with its recorded oil fraction; every particle that stays active moves,
// and exchanges oil with the others, by the model alone.

#include <torch/torch.h>

#include <functional>
#include <vector>

#include "gnn/data/dataset.h"
#include "gnn/models/learned_simulator.h"

namespace gnn {

struct RolloutResult {
  int64_t first_frame = 0;     // the recorded frame the rollout starts from
  torch::Tensor position;      // [F + 1, N, 3]: frame 0 is the recorded start; inactive rows copy
                               // the recording (they are not predictions)
  torch::Tensor active;        // [F + 1, N] bool
  torch::Tensor oil_fraction;  // [F + 1, N] float32, likewise
  std::vector<double> frame_seconds;  // wall time of each predicted frame
  // Standalone rollouts: inflow layers the pool of returned water could not fill (the forecast
  // backed the reach up; RiverFlow::skipped_layers). 0 for replayed ones.
  long skipped_inflow_layers = 0;
};

// Frames first_frame + 1 .. first_frame + frames (which must exist in the trajectory).
// `on_frame(k)` is called after each predicted frame (for progress). `correct`, when given, may
// move the predicted positions [n, 3] of the particles that were active (with their new oil
// fractions [n]) before they enter the history: the SPH relaxation of infer's --relax.
using FrameCorrection = std::function<void(torch::Tensor& position, const torch::Tensor& fraction)>;
RolloutResult rollout(LearnedSimulator& simulator, const Trajectory& trajectory,
                      int64_t first_frame, int64_t frames, double frame_dt,
                      const std::function<void(int64_t)>& on_frame = {},
                      const FrameCorrection& correct = {});

// Mean squared error of one-step predicted positions (m^2, averaged over dimensions and over the
// fluid particles active at both frames) at each of `frames` (each >= 0, < T - 1).
double one_step_position_mse(LearnedSimulator& simulator, const Trajectory& trajectory,
                             const std::vector<int64_t>& frames, double frame_dt);

}  // namespace gnn
