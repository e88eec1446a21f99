#include "train/pushforward.h"

#include <algorithm>

#include "common/config_error.h"
#include "gnn/data/frame_window.h"

namespace train {

int most_pushforward_frames(const TrainingConfig& config) {
  int most = config.pushforward_steps;
  for (const auto& stage : config.pushforward_schedule) most = std::max(most, stage.unrolls);
  return most;
}

int frames_per_window(const TrainingConfig& config) {
  return int(gnn::kWindow) + most_pushforward_frames(config) + config.loss_frames;
}

int pushforward_frames(const TrainingConfig& config, int64_t step, std::mt19937_64& sampler) {
  const auto& stages = config.pushforward_schedule;
  if (stages.empty()) return config.pushforward_steps;
  double open_weight = 0;
  size_t open = 0;
  while (open < stages.size() && stages[open].from_step <= step)
    open_weight += stages[open++].weight;
  // A uniform draw placed on the open stages' cumulative weights (std::discrete_distribution's
  // draw is not specified alike across standard libraries; this one is).
  double u = std::uniform_real_distribution<double>(0.0, open_weight)(sampler);
  for (size_t k = 0; k + 1 < open; ++k) {
    if (u < stages[k].weight) return stages[k].unrolls;
    u -= stages[k].weight;
  }
  return stages[open - 1].unrolls;
}

void check_pushforward(const TrainingConfig& config, const std::string& file) {
  const auto& stages = config.pushforward_schedule;
  if (stages.empty()) return;
  if (config.pushforward_steps != 0)
    throw common::ConfigError(file, "/pushforward_steps",
                              "a fixed unroll count beside /pushforward_schedule: give one of "
                              "the two (a one-stage schedule unrolls a fixed count)");
  if (stages.front().from_step != 0)
    throw common::ConfigError(file, "/pushforward_schedule/0/from_step",
                              "the first stage must open at step 0 (the steps before it would "
                              "have no unroll count to draw)");
  for (size_t k = 1; k < stages.size(); ++k)
    if (stages[k].from_step < stages[k - 1].from_step)
      throw common::ConfigError(
          file, "/pushforward_schedule/" + std::to_string(k) + "/from_step",
          "opens at step " + std::to_string(stages[k].from_step) + ", before the stage above it (" +
              std::to_string(stages[k - 1].from_step) + "): stages are listed in step order");
}

}  // namespace train
