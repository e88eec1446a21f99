// spill-train: trains a learned simulator on a dataset of the data contract, read from a folder
// or simulated in this process from a scene.
//   spill-train --config configs/training/gns_smoke.json --data DIR --out RUN
//               [--resume] [--threads N] [--set /pointer=value ...]
//   spill-train --config FILE --scene SCENE --trajectories N --out RUN [--vary /pointer=LO:HI ...]
//               [--seed K] [--split 0.8/0.1/0.1] [--frames F] [--warm-up S]
//               [--set-scene /pointer=value ...] [--save-data DIR] [--resume] [--threads N] ...
#include <CLI/CLI.hpp>
#include <iostream>

#include "common/command_line.h"
#include "common/exit_codes.h"
#include "common/hdf5_handles.h"
#include "common/stop_signals.h"
#include "train/command_line.h"

int main(int argc, char** argv) {
  common::skip_hdf5_exit_handler();
  CLI::App app{"Train a learned particle simulator (GNS, DPI-Nets, PAGATNet) on spill data"};
  train::TrainCommandLine command;
  train::add_training_options(app, command);
  if (const auto stop = common::parse_command_line(app, argc, argv)) return *stop;
  // Ctrl-C and SIGTERM stop the simulation or the training at the next trajectory or step:
  // the last checkpoint is kept, no staging folder is left, the exit code is 130.
  common::catch_stop_signals();
  command.options.stop = common::stop_flag();
  try {
    train::run_training(command);
  } catch (const std::exception& e) {
    return common::report_error(std::cerr, "spill-train", e);
  }
  return 0;
}
