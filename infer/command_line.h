#pragma once
// spill-infer's command line: one function per subcommand adds its options (the work is in
// infer/*_command.cpp); main.cpp dispatches.

#include <CLI/CLI.hpp>
#include <string>

#include "infer/commands.h"

namespace infer {

// spill-infer export: a weights-only copy of a checkpoint.
struct ExportOptions {
  std::string from, to;
  bool force = false;  // replace an existing --out that is itself a checkpoint
};

CLI::App* add_rollout_command(CLI::App& app, RolloutOptions& options);
CLI::App* add_eval_command(CLI::App& app, EvalOptions& options);
CLI::App* add_compare_command(CLI::App& app, CompareOptions& options);
CLI::App* add_predict_command(CLI::App& app, PredictOptions& options);
CLI::App* add_export_command(CLI::App& app, ExportOptions& options);

}  // namespace infer
