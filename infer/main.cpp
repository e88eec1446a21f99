// spill-infer: runs a trained learned simulator.
//   spill-infer rollout --checkpoint C --data DIR --split test --trajectory K --from T0
//                       --frames F --out OUT
//   spill-infer eval    --checkpoint C --data DIR --split test --out OUT
//   spill-infer compare --checkpoints A B ... [--constant-velocity] --data DIR --split test
//                       --out OUT [--from T0] [--frames F]
//   spill-infer predict --checkpoint C --scene FILE --out DIR [--set /pointer=value ...]
//                       [--initial-state FILE] [--end-time T] [--png] [--relax K]
//   spill-infer export  --checkpoint C --out C_WEIGHTS.pt [--force]   (no optimiser state)
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <iostream>

#include "common/command_line.h"
#include "common/exit_codes.h"
#include "common/hdf5_handles.h"
#include "common/stop_signals.h"
#include "gnn/runtime/runtime.h"
#include "gnn/training/checkpoint.h"
#include "infer/command_line.h"

int main(int argc, char** argv) {
  common::skip_hdf5_exit_handler();
  CLI::App app{"Roll out and evaluate a learned particle simulator"};
  app.require_subcommand(1);
  infer::RolloutOptions rollout;
  infer::EvalOptions eval;
  infer::CompareOptions compare;
  infer::ExportOptions exported;
  infer::PredictOptions predict;
  auto* r = infer::add_rollout_command(app, rollout);
  infer::add_eval_command(app, eval);
  auto* c = infer::add_compare_command(app, compare);
  auto* x = infer::add_export_command(app, exported);
  auto* p = infer::add_predict_command(app, predict);
  if (const auto stop = common::parse_command_line(app, argc, argv)) return *stop;
  // Ctrl-C and SIGTERM stop a rollout at its next frame: its staging folder is removed and the
  // exit code is 130. (export writes one file atomically and needs no stop.)
  common::catch_stop_signals();
  rollout.common.stop = eval.common.stop = compare.stop = predict.stop = common::stop_flag();
  try {
    if (x->parsed()) {
      gnn::write_weights_only(exported.from, exported.to, exported.force);
      std::cerr << "weights of " << exported.from << " written to " << exported.to << "\n";
    } else if (p->parsed()) {
      predict.log = &std::cerr;
      predict.terminal = isatty(STDERR_FILENO) != 0;
      const nlohmann::json summary = infer::run_predict(predict);
      std::cout << "wrote " << predict.out_dir << ": " << summary["frames"] << " learned frames in "
                << summary["wall_s"].get<double>() << " s, " << summary["fluid_particles"]
                << " fluid particles\n";
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
