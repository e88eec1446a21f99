// spill-sim reach --config FILE --out DIR [--set /pointer=value ...] [--threads N] [--force]
// spill-sim reach-doc
// spill-sim reach-bench [--cells N ...] [--steps S] [--threads T]
// The depth-averaged flow of a river reach on real terrain (reach/reach_run.h): rasters of
// depth, level and velocity, the event's maxima, map pictures and reach.json.

#include <unistd.h>

#include <iostream>
#include <memory>

#include "common/command_line.h"
#include "reach/reach_benchmark.h"
#include "reach/reach_run.h"
#include "sim/commands/command.h"
#include "sph/app/scene_runner.h"

namespace sim {

namespace {
struct ReachCommandOptions {
  reach::ReachRunOptions run;
  int threads = 0;
};
}  // namespace

Command add_reach_command(CLI::App& app, const CommandContext& context) {
  auto o = std::make_shared<ReachCommandOptions>();
  auto* c = app.add_subcommand(
      "reach",
      "Run the 2D shallow-water flow of a river reach on a terrain raster; write GeoTIFF rasters, "
      "map pictures and reach.json");
  c->add_option("--config", o->run.config_file, "Reach config JSON (docs/reach.md)")->required();
  c->add_option("--out", o->run.out_dir, "Output folder (not replaced unless --force)")->required();
  c->add_option("--set", o->run.overrides, "Override a config value: /json/pointer=value");
  c->add_option("--threads", o->threads, "OpenMP threads (default: all cores)")
      ->check(common::positive());
  c->add_flag("--force", o->run.force,
              "Replace an earlier reach folder (only one of ours; removed after the new run)");
  c->footer(
      "Exit code: 0 on success; 1 when the run failed; 2 for bad input (a config key, a raster "
      "GDAL cannot open, no or a geographic CRS, a window or section off the raster, a refused "
      "--out); 130 when interrupted. Nothing is written unless the run finishes.");
  return {c, [o, context] {
            context.catch_stop_signals();
            reach::ReachRunOptions run = o->run;
            run.threads = use_threads(o->threads);
            run.stop = context.stop;
            run.log = &std::cerr;
            run.terminal = isatty(STDERR_FILENO) != 0;
            const nlohmann::json summary = reach::run_reach(run);
            const auto& grid = summary["grid"];
            std::cout << "wrote " << run.out_dir << ": " << grid["nx"] << " x " << grid["ny"]
                      << " cells of " << grid["dx_m"] << " m, " << summary["steps"]
                      << " steps to t = " << summary["end_time_s"] << " s"
                      << (summary["steady"]["reached"].get<bool>() ? " (steady)" : "")
                      << ", volume balance error " << summary["volume_balance"]["error_m3"]
                      << " m3\n";
            return 0;
          }};
}

Command add_reach_bench_command(CLI::App& app, const CommandContext&) {
  auto cells = std::make_shared<std::vector<long>>(std::vector<long>{62500, 125000, 250000});
  auto steps = std::make_shared<int>(200);
  auto threads = std::make_shared<int>(0);
  auto* c = app.add_subcommand(
      "reach-bench",
      "Time the reach's shallow-water solver on straight valleys of growing size; print JSON");
  c->add_option("--cells", *cells, "Cell counts to time (default 62500 125000 250000)");
  c->add_option("--steps", *steps, "Steps timed per size (after 20 untimed)")
      ->check(common::positive());
  c->add_option("--threads", *threads, "OpenMP threads (default: all cores)")
      ->check(common::positive());
  return {c, [cells, steps, threads] {
            const int used = use_threads(*threads);
            const nlohmann::json out = {
                {"benchmark", "reach shallow water (reach/reach_benchmark.h)"},
                {"machine", sph::machine_description(used)},
                {"rows", reach::benchmark_reach(*cells, *steps, 20)}};
            std::cout << out.dump(2) << "\n";
            return 0;
          }};
}

Command add_reach_doc_command(CLI::App& app, const CommandContext&) {
  auto* c = app.add_subcommand(
      "reach-doc",
      "Print every key of a reach config as a Markdown table (docs/reach_reference.md)");
  return {c, [] {
            std::cout << reach::reach_reference_markdown();
            return 0;
          }};
}

}  // namespace sim
