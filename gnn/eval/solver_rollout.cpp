#include "gnn/eval/solver_rollout.h"

#include <stdexcept>
#include <string>

#include "gnn/eval/scene_rollout.h"

namespace gnn {

RolloutResult solver_rollout(const Trajectory& t, int64_t first_frame, int64_t frames,
                             double frame_dt, double jitter, uint64_t seed,
                             const std::function<void(int64_t)>& on_frame) {
  if (!(jitter >= 0)) throw std::invalid_argument("solver rollout: jitter must be >= 0");
  RestartedRollout rollout = restart_rollout(t, first_frame, frames, frame_dt, jitter, seed);
  sph::Simulation& sim = *rollout.simulation;
  const double start_time = sim.time();
  record_frames(
      rollout,
      [&](int64_t k) { sim.advance_to(start_time + double(k) * frame_dt, int(first_frame + k)); },
      on_frame);
  return std::move(rollout.result);
}

}  // namespace gnn
