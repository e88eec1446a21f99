#pragma once
// One spill-sim subcommand per file: its options, added to the command line, and what it runs
// once they are parsed. main.cpp only dispatches; the work itself is in the sph library.

#include <CLI/CLI.hpp>
#include <atomic>
#include <functional>

namespace sim {

// What a subcommand may use of the process: the stop flag that Ctrl-C and SIGTERM set once
// catch_stop_signals() was called (a run then removes its staging folder and exits 130).
struct CommandContext {
  const std::atomic<bool>* stop = nullptr;
  void (*catch_stop_signals)() = nullptr;
};

// A subcommand added to the command line: `run` is called when it was chosen and returns the
// exit code; errors are thrown for main to report.
struct Command {
  CLI::App* cli = nullptr;
  std::function<int()> run;
};

Command add_run_command(CLI::App& app, const CommandContext& context);
Command add_bench_command(CLI::App& app, const CommandContext& context);
Command add_generate_command(CLI::App& app, const CommandContext& context);
Command add_compare_command(CLI::App& app, const CommandContext& context);
Command add_scene_doc_command(CLI::App& app, const CommandContext& context);
Command add_reach_command(CLI::App& app, const CommandContext& context);
Command add_reach_doc_command(CLI::App& app, const CommandContext& context);
Command add_reach_bench_command(CLI::App& app, const CommandContext& context);
Command add_forecast_command(CLI::App& app, const CommandContext& context);
Command add_forecast_doc_command(CLI::App& app, const CommandContext& context);
Command add_forecast_bench_command(CLI::App& app, const CommandContext& context);

// Sets OpenMP's thread count to `requested` (every core when 0) and flushes subnormals to zero,
// as every simulation runs; returns the count.
int use_threads(int requested);

}  // namespace sim
