#pragma once
// How many frames a training window is rolled forward by the model itself, without gradient,
// before its loss frame ("pushforward", Brandstetter et al. 2022): the model then learns from
// inputs carrying its own errors, as a standalone forecast's do. Either a fixed count
// (`pushforward_steps`) or LagrangeBench's schedule (`pushforward_schedule`): stages that open
// at a training step, each stage's unroll count drawn with its weight among the stages open so
// far, so that early training sees recorded inputs and later training more and longer unrolls.

#include <cstdint>
#include <random>
#include <string>

#include "train/training_config.h"

namespace train {

// The most frames any window may be unrolled (what the data's trajectories must leave room for).
int most_pushforward_frames(const TrainingConfig& config);

// The recorded frames a training window reads: the input window, the frames pushed forward and
// one target per loss frame.
int frames_per_window(const TrainingConfig& config);

// The unroll count of the batch at `step`: the fixed count, or one stage's count drawn from the
// stages open at `step` with their weights. Draws from `sampler` only when a schedule is set, so
// that runs without one keep their random streams.
int pushforward_frames(const TrainingConfig& config, int64_t step, std::mt19937_64& sampler);

// Refuses a schedule that cannot be followed, naming `file` and the key: a first stage that
// does not open at step 0, stages out of step order, a schedule beside a fixed count.
void check_pushforward(const TrainingConfig& config, const std::string& file);

}  // namespace train
