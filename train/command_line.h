#pragma once
// spill-train's command line: its options (a dataset folder or a scene simulated in-process with
// spill-sim generate's options) and the run they ask for. main.cpp only parses and reports.

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "train/scene_data.h"
#include "train/trainer.h"

namespace train {

struct TrainCommandLine {
  TrainerOptions options;
  SceneDataOptions scene;
  int threads = 2;
  int blas_threads = 0;
  std::string split = "0.8/0.1/0.1";
  std::vector<std::string> vary;
  std::string device = "cpu";
  double collective_timeout_s = 300;  // a data-parallel launch: how long a rank waits for the rest
  CLI::Option* scene_option = nullptr;  // --scene: simulate the data in this process
};

void add_training_options(CLI::App& app, TrainCommandLine& c);

// Trains as the parsed options ask; throws what the trainer or the data throw.
void run_training(TrainCommandLine& c);

}  // namespace train
