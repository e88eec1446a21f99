#pragma once
// Windows of recorded positions: the last 6 positions (5 velocities) of the fluid particles
// active at a frame, the input every model takes.
//
// A particle emitted (or recycled to the inflow) inside the window has no real history before
// it became active; its earlier positions are extrapolated back from its first active frame
// along its recorded velocity, as if it had arrived at the emitter's speed. Training and rollout
// use the same rule, so a rollout meets newly emitted particles the way training showed them.

#include <torch/torch.h>

#include "gnn/data/dataset.h"

namespace gnn {

constexpr int64_t kWindow = 6;

// Positions [n, 6, 3] (oldest first) of particles `ids` at frames frame-5 .. frame; every one
// of them must be active at `frame`.
torch::Tensor position_history(const Trajectory& t, int64_t frame, const torch::Tensor& ids,
                               double frame_dt);

// History [6, 3] of one particle that becomes active at `frame`: its recorded position there and
// positions stepped back along its recorded velocity.
torch::Tensor launched_history(const Trajectory& t, int64_t frame, int64_t particle,
                               double frame_dt);

// Histories [n, 6, 3] of particles that become active at positions [n, 3] with velocities
// [n, 3] (m/s): the same rule for particles launched by a scene's own sources.
torch::Tensor launched_histories(const torch::Tensor& position, const torch::Tensor& velocity,
                                 double frame_dt);

// Indices of the particles active at `frame`, int64.
inline torch::Tensor active_ids(const Trajectory& t, int64_t frame) {
  return t.active[frame].nonzero().view(-1);
}

}  // namespace gnn
