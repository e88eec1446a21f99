// spill-sim compare --scene FILE --solvers wcsph,dfsph,... --frames T1,T2,... --out DIR
//                   [--set /pointer=value ...] [--threads N] [--force]
// Runs the scene with each solver to the last of the frame counts and writes table.json,
// table.md (wall time to each moment, throughput, iterations, density error, spill metrics) and
// views.png (a column per solver, a row per moment); exits 1 only when every solver failed (see
// solver_table.h).

#include <unistd.h>

#include <iostream>
#include <memory>

#include "common/command_line.h"
#include "sim/commands/command.h"
#include "sph/app/solver_table.h"

namespace sim {

namespace {
struct CompareCommandOptions {
  sph::SolverTableRequest table;
  std::string solvers, frames;  // comma-separated, split by common::split_list
  std::string out_dir;
  int threads = 0;
};
}  // namespace

Command add_compare_command(CLI::App& app, const CommandContext& context) {
  auto o = std::make_shared<CompareCommandOptions>();
  auto* c = app.add_subcommand(
      "compare",
      "Run a scene with each solver; write a table (table.md, table.json) and a picture grid "
      "(views.png)");
  c->add_option("--scene", o->table.scene_file, "Scene JSON file")->required();
  c->add_option("--solvers", o->solvers,
                "Registered solvers, comma-separated, in column order (e.g. wcsph,dfsph,mtdf)")
      ->required();
  c->add_option("--frames", o->frames,
                "Moments, increasing, in frames of the scene's output/frame_dt, "
                "comma-separated (e.g. 40,80,120); every solver runs to the last")
      ->required();
  c->add_option("--out", o->out_dir, "Output folder (not replaced unless --force)")->required();
  c->add_option("--set", o->table.overrides, "Override a scene value: /json/pointer=value");
  c->add_option("--threads", o->threads, "OpenMP threads (default: all cores)")
      ->check(common::positive());
  c->add_flag("--force", o->table.force,
              "Replace an earlier compare folder (removed after the new one is written)");
  c->footer(
      "A solver that fails is marked in the table with its frame and reason, its later pictures "
      "are grey, and the others still run. Exit code: 0 when at least one solver finished; 1 "
      "when every solver failed (nothing is written); 2 for bad input (an unknown solver, a bad "
      "scene or option, a refused --out); 130 when interrupted (nothing is written).");
  return {c, [o, context] {
            context.catch_stop_signals();
            sph::SolverTableRequest table = o->table;
            table.solvers = common::split_list(o->solvers, "--solvers");
            table.frames = common::split_int_list(o->frames, "--frames");
            table.out_dir = o->out_dir;
            table.threads = use_threads(o->threads);
            table.stop = context.stop;
            table.log = &std::cerr;
            table.terminal = isatty(STDERR_FILENO) != 0;
            const nlohmann::json written = sph::write_solver_table(table);
            int failed = 0;
            for (const auto& row : written["rows"]) failed += row["status"] != "ok";
            std::cout << "wrote " << o->out_dir << ": " << written["rows"].size() << " solvers"
                      << (failed ? " (" + std::to_string(failed) + " failed, see table.md)" : "")
                      << ", views.png " << written["views"]["width"] << " x "
                      << written["views"]["height"] << "\n";
            return 0;
          }};
}

}  // namespace sim
