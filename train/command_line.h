#pragma once
// spill-train's command line: its options (a dataset folder or a scene simulated in-process with
// spill-sim generate's options) and the run they ask for. main.cpp only parses and reports.

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "sph/generation/generation_command_line.h"
#include "train/scene_data.h"
#include "train/trainer.h"

namespace train {

struct TrainCommandLine {
  TrainerOptions options;
  SceneDataOptions scene;
  int threads = 2;
  int blas_threads = 0;
  sph::GenerationOptionText generation;  // --vary and --split as given
  std::string device = "cpu";
  double collective_timeout_s = 300;  // a data-parallel launch: how long a rank waits for the rest
  CLI::Option* scene_option = nullptr;  // --scene: simulate the data in this process
};

void add_training_options(CLI::App& app, TrainCommandLine& c);

// Trains as the parsed options ask; throws what the trainer or the data throw.
void run_training(TrainCommandLine& c);

}  // namespace train
