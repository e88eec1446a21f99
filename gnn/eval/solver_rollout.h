#pragma once
// The ceiling a learned simulator is measured against: the simulator that made the data, run
// again from a recorded frame whose active positions are jittered by a tiny amount. How far that
// run drifts from the recording is the spread of the simulator itself: no model can be expected
// to predict the recording more closely than its own solver started a hair away. Issue 30 asks
// for a jitter of 1e-3 of a particle diameter.

#include <cstdint>
#include <functional>

#include "gnn/data/dataset.h"
#include "gnn/eval/rollout.h"

namespace gnn {

// Runs the trajectory's scene (t.scene, its own solver, sources and sinks) from recorded frame
// `first_frame` for `frames` frames of `frame_dt`, the active particles' positions first moved
// by independent uniform offsets in [-jitter, jitter] m per coordinate (seeded by `seed`).
// Result as standalone_rollout's (frame_seconds: the solver's wall time). Throws DatasetError as
// simulation_at_frame, std::invalid_argument for frames outside the recording or a negative
// jitter; the solver's SimulationError passes through.
RolloutResult solver_rollout(const Trajectory& t, int64_t first_frame, int64_t frames,
                             double frame_dt, double jitter, uint64_t seed,
                             const std::function<void(int64_t)>& on_frame = {});

}  // namespace gnn
