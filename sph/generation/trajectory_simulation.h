#pragma once
// The pipeline's second step: one planned trajectory simulated into a sink.

#include <nlohmann/json.hpp>
#include <string>

#include "sph/generation/generation.h"

namespace sph {

// Simulates one planned trajectory with subnormals flushed (floating_point.h, as spill-sim does)
// and hands its recorded frames to `sink`: from the warm-up (options.warm_up, or the earliest
// leak's start when < 0) for options.frames frames (to the scene's end when 0). Returns its
// description: index, split, parameters, particles, frames, first_frame_time, sph_wall_s,
// sph_seconds_per_frame, simulation_threads (the fewest OpenMP threads a frame began with), and
// velocity_moments and acceleration_moments (the sums behind the normalisation statistics).
nlohmann::json simulate_trajectory(const GenerateOptions& options, const TrajectoryPlan& plan,
                                   TrajectorySink& sink);

}  // namespace sph
