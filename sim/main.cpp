// spill-sim: SPH scenes, reaches and forecasts. A dispatcher: each subcommand's options and run
// are in sim/commands/ (one file each); the work is in the sph, reach and farfield libraries.
//   spill-sim run --scene FILE --out DIR [--set /pointer=value ...] [--threads N] [--ply] [--png]
//                 [--force] [--save-state-at T] [--initial-state FILE]
//   spill-sim bench [--scene FILE] [--radius R ...] [--threads N] [--set ...]
//   spill-sim bench --scene FILE --compare mtdf,dfsph [--repeat N] [--threads N] [--set ...]
//   spill-sim generate --scene FILE --trajectories N --out DIR [--vary /pointer=LO:HI ...]
//                      [--seed S] [--split 0.8/0.1/0.1] [--frames F] [--warm-up S] [--threads N]
//   spill-sim compare --scene FILE --solvers wcsph,dfsph,... --frames T1,T2,... --out DIR
//                     [--set /pointer=value ...] [--threads N] [--force]
//   spill-sim scene-doc
//   spill-sim reach --config FILE --out DIR [--set /pointer=value ...] [--threads N] [--force]
//   spill-sim reach-doc
//   spill-sim reach-bench [--cells N ...] [--steps S] [--threads T]
//   spill-sim forecast --config FILE --out DIR [--set /pointer=value ...] [--threads N] [--force]
//   spill-sim forecast-doc
//   spill-sim forecast-bench [--elements N ...] [--hours H] [--step S] [--threads T]

#include <CLI/CLI.hpp>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/command_line.h"
#include "common/exit_codes.h"
#include "common/hdf5_handles.h"
#include "common/stop_signals.h"
#include "sim/commands/command.h"

int main(int argc, char** argv) {
  common::skip_hdf5_exit_handler();
  CLI::App app{"spill-sim: two-phase SPH simulation of oil spills in rivers"};
  app.require_subcommand(1);
  const sim::CommandContext context{common::stop_flag(), &common::catch_stop_signals};
  const std::vector<sim::Command> commands = {
      sim::add_run_command(app, context),
      sim::add_bench_command(app, context),
      sim::add_generate_command(app, context),
      sim::add_compare_command(app, context),
      sim::add_scene_doc_command(app, context),
      sim::add_reach_command(app, context),
      sim::add_reach_doc_command(app, context),
      sim::add_reach_bench_command(app, context),
      sim::add_forecast_command(app, context),
      sim::add_forecast_doc_command(app, context),
      sim::add_forecast_bench_command(app, context),
  };
  if (const auto stop = common::parse_command_line(app, argc, argv)) return *stop;
  // What each command allocates, for an out-of-memory message that says how to make it smaller.
  std::string smaller = "use fewer or larger particles";
  try {
    for (const auto& command : commands) {
      if (!command.cli->parsed()) continue;
      const std::string name = command.cli->get_name();
      if (name.rfind("reach", 0) == 0)
        smaller = "run a smaller /terrain/window or a larger /terrain/coarsen";
      else if (name.rfind("forecast", 0) == 0)
        smaller = "release fewer elements, write outputs less often or use longer bank bins";
      return command.run();
    }
  } catch (const std::exception& e) {
    return common::report_error(std::cerr, "spill-sim", e, smaller);
  }
  return 0;
}
