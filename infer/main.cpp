// spill-infer: runs a trained learned simulator.
//   spill-infer rollout --checkpoint C --data DIR --split test --trajectory K --from T0
//                       --frames F --out OUT
//   spill-infer eval    --checkpoint C --data DIR --split test --out OUT
//   spill-infer compare --checkpoints A B ... [--constant-velocity] --data DIR --split test
//                       --out OUT [--from T0] [--frames F]
//   spill-infer export  --checkpoint C --out C_WEIGHTS.pt [--force]   (no optimiser state)
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
#include "infer/commands.h"

namespace {
void add_common(CLI::App* c, infer::CommonOptions& o) {
  c->add_option("--checkpoint", o.checkpoint, "checkpoint (*.pt) written by spill-train")
      ->required();
  c->add_option("--data", o.data_dir, "dataset folder (metadata.json and <split>.h5)")
      ->required()
      ->check(CLI::ExistingDirectory);
  c->add_option("--split", o.split, "split to run on")
      ->check(CLI::IsMember({"train", "valid", "test"}));
  c->add_option("--out", o.out_dir, "output folder")->required();
  c->add_option("--threads", o.threads,
                "cores to use; the LibTorch/BLAS split is chosen for the model (see "
                "inference_runtime in gnn/runtime/runtime.h) unless --blas-threads is given")
      ->check(CLI::PositiveNumber);
  c->add_option("--blas-threads", o.blas_threads,
                "OpenBLAS threads, with --threads LibTorch threads (default: the measured best "
                "split for the model)")
      ->check(CLI::PositiveNumber);
  c->add_option("--device", o.device, "where the model runs: cpu (default) or cuda[:N]");
  c->add_option("--relax", o.relax,
                "after each learned frame, this many iterations of the simulator's "
                "constant-density correction on the predicted positions (default 0: off)")
      ->check(CLI::NonNegativeNumber);
}
}  // namespace

int main(int argc, char** argv) {
  common::skip_hdf5_exit_handler();
  CLI::App app{"Roll out and evaluate a learned particle simulator"};
  app.require_subcommand(1);
  infer::RolloutOptions rollout;
  auto* r = app.add_subcommand("rollout", "predict a trajectory and draw it beside the truth");
  add_common(r, rollout.common);
  r->add_option("--trajectory", rollout.trajectory, "trajectory index in the split")
      ->check(CLI::NonNegativeNumber);
  r->add_option("--from", rollout.from, "recorded frame to start from")
      ->check(CLI::NonNegativeNumber);
  r->add_option("--frames", rollout.frames, "frames to predict (default: to the end)")
      ->check(CLI::PositiveNumber);
  r->add_option("--png-every", rollout.png_every, "draw every n-th frame")
      ->check(CLI::PositiveNumber);
  infer::EvalOptions eval;
  auto* e = app.add_subcommand("eval", "accuracy and speed over every trajectory of a split");
  add_common(e, eval.common);
  e->add_option("--from", eval.from, "recorded frame each rollout starts from")
      ->check(CLI::NonNegativeNumber);
  e->add_option("--frames", eval.frames, "frames per rollout (default: to the end)")
      ->check(CLI::PositiveNumber);
  infer::CompareOptions compare;
  auto* c = app.add_subcommand(
      "compare", "several models (and the constant-velocity floor) on the same trajectories");
  c->add_option("--checkpoints", compare.checkpoints, "checkpoints (*.pt) written by spill-train")
      ->check(CLI::ExistingFile);
  c->add_flag("--constant-velocity", compare.constant_velocity,
              "add the constant-velocity floor (every particle keeps its last velocity)");
  c->add_option("--data", compare.data_dir, "dataset folder (metadata.json and <split>.h5)")
      ->required()
      ->check(CLI::ExistingDirectory);
  c->add_option("--split", compare.split, "split to run on")
      ->check(CLI::IsMember({"train", "valid", "test"}));
  c->add_option("--out", compare.out_dir, "output folder")->required();
  c->add_option("--from", compare.from, "recorded frame each rollout starts from")
      ->check(CLI::NonNegativeNumber);
  c->add_option("--frames", compare.frames, "frames per rollout (default: to the end)")
      ->check(CLI::PositiveNumber);
  c->add_option("--threads", compare.threads,
                "cores to use; each model gets its measured best LibTorch/BLAS split unless "
                "--blas-threads is given")
      ->check(CLI::PositiveNumber);
  c->add_option("--blas-threads", compare.blas_threads, "OpenBLAS threads for every model")
      ->check(CLI::PositiveNumber);
  c->add_option("--device", compare.device, "where the models run: cpu (default) or cuda[:N]");
  c->add_option("--relax", compare.relax,
                "after each learned frame, this many iterations of the simulator's "
                "constant-density correction on the predicted positions (default 0: off)")
      ->check(CLI::NonNegativeNumber);
  std::string export_from, export_to;
  auto* x = app.add_subcommand(
      "export", "a weights-only copy of a checkpoint (no optimiser state), to share or commit");
  x->add_option("--checkpoint", export_from, "checkpoint (*.pt) written by spill-train")
      ->required()
      ->check(CLI::ExistingFile);
  x->add_option("--out", export_to, "the copy (*.pt); training cannot resume from it")->required();
  bool export_force = false;
  x->add_flag("--force", export_force,
              "replace an existing --out, only if it is itself a checkpoint (atomically)");
  if (const auto stop = common::parse_command_line(app, argc, argv)) return *stop;
  try {
    if (x->parsed()) {
      gnn::write_weights_only(export_from, export_to, export_force);
      std::cerr << "weights of " << export_from << " written to " << export_to << "\n";
    } else if (r->parsed()) {
      gnn::configure_runtime(gnn::inference_runtime(rollout.common.threads));
      rollout.common.log = &std::cerr;
      infer::run_rollout(rollout);
    } else if (c->parsed()) {
      gnn::configure_runtime(gnn::inference_runtime(compare.threads));
      compare.log = &std::cerr;
      infer::run_compare(compare);
    } else {
      gnn::configure_runtime(gnn::inference_runtime(eval.common.threads));
      eval.common.log = &std::cerr;
      infer::run_eval(eval);
    }
  } catch (const std::exception& e) {
    return common::report_error(std::cerr, "spill-infer", e);
  }
  return 0;
}
