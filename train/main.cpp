// spill-train: trains a learned simulator on a dataset of the data contract.
//   spill-train --config configs/training/gns_smoke.json --data DIR --out RUN
//               [--resume] [--threads N] [--set /pointer=value ...]
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <iostream>

#include "common/command_line.h"
#include "common/config_error.h"
#include "common/exit_codes.h"
#include "common/hdf5_handles.h"
#include "common/output_folder.h"
#include "gnn/data/dataset.h"
#include "gnn/runtime/runtime.h"
#include "gnn/training/checkpoint.h"
#include "train/trainer.h"

int main(int argc, char** argv) {
  common::skip_hdf5_exit_handler();
  CLI::App app{"Train a learned particle simulator (GNS) on spill trajectories"};
  train::TrainerOptions options;
  int threads = 2;
  int blas_threads = 0;
  app.add_option("--config", options.config_file, "training config (configs/training/*.json)")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--data", options.data_dir,
                 "dataset folder (metadata.json, train.h5, valid.h5) from spill-sim generate")
      ->required()
      ->check(CLI::ExistingDirectory);
  app.add_option("--out", options.out_dir, "run folder: log.csv, loss.svg, last.pt")->required();
  app.add_flag("--resume", options.resume, "continue from RUN/last.pt");
  app.add_option("--threads", threads,
                 "cores to use; the LibTorch/BLAS split is chosen for the model (see "
                 "training_runtime in gnn/runtime/runtime.h) unless --blas-threads is given")
      ->check(CLI::PositiveNumber);
  app.add_option("--blas-threads", blas_threads,
                 "OpenBLAS threads, with --threads LibTorch threads (default: the measured best "
                 "split for the model)")
      ->check(CLI::PositiveNumber);
  app.add_option("--set", options.overrides,
                 "override a training config value: /pointer=value (e.g. /steps=200, "
                 "/model/latent=64)");
  std::string device = "cpu";
  app.add_option("--device", device, "where the model trains: cpu (default) or cuda[:N]");
  if (const auto stop = common::parse_command_line(app, argc, argv)) return *stop;
  gnn::configure_runtime({threads, blas_threads});
  options.log = &std::cerr;
  options.terminal = isatty(2);
  try {
    options.out_dir = common::normalise_output_path(options.out_dir).string();
    options.device = gnn::parse_device(device);
    train::Trainer trainer(options);
    if (blas_threads == 0) {
      const gnn::GraphModel& model = trainer.simulator().model();
      const gnn::RuntimeSettings mix = gnn::training_runtime(threads, model.trains_in_chunks());
      gnn::configure_runtime(mix);
      std::cerr << "threads: " << mix.threads << " LibTorch, " << mix.blas_threads
                << " BLAS (the measured best split for " << model.name() << " on " << threads
                << ")\n";
    }
    const double loss = trainer.run();
    std::cout << "trained to step " << trainer.step() << ", loss " << loss << "; run in "
              << options.out_dir << "\n";
  } catch (const std::exception& e) {
    return common::report_error(std::cerr, "spill-train", e);
  }
  return 0;
}
