// spill-sim forecast --config FILE --out DIR [--set /pointer=value ...] [--threads N] [--force]
//                    [--shard I/N | --members-from SHARDS_DIR]
// spill-sim forecast-doc
// spill-sim forecast-bench [--elements N ...] [--hours H] [--step S] [--threads T]
// The far field: oil released on a finished reach run's flow, drifting, spreading, weathering
// and stranding (farfield/forecast_run.h). Here, where the near field and the far field meet,
// a config's near field is run first and its oil handed over as it leaves the box
// (sph/app/near_field_handover.h, sim/far_field_parcels.h); the pictures become a video
// (sph/io/animation.h).

#include <unistd.h>

#include <iostream>
#include <memory>

#include "common/array_task.h"
#include "common/command_line.h"
#include "common/exit_codes.h"
#include "farfield/far_field_benchmark.h"
#include "farfield/forecast_run.h"
#include "sim/commands/command.h"
#include "sim/far_field_parcels.h"
#include "sph/app/near_field_handover.h"
#include "sph/app/scene_runner.h"
#include "sph/io/animation.h"

namespace sim {

namespace {
struct ForecastCommandOptions {
  farfield::ForecastRunOptions run;
  std::string shard;
  int threads = 0;
  bool no_pictures = false;
};
}  // namespace

Command add_forecast_command(CLI::App& app, const CommandContext& context) {
  auto o = std::make_shared<ForecastCommandOptions>();
  auto* c = app.add_subcommand(
      "forecast",
      "Forecast an oil slick kilometres down a river on a reach run's flow: drift, spreading, "
      "weathering, stranding; write forecast.json, GeoJSON, NetCDF, the budget and maps");
  c->add_option("--config", o->run.config_file, "Forecast config JSON (docs/far_field.md)")
      ->required();
  c->add_option("--out", o->run.out_dir, "Output folder (not replaced unless --force)")->required();
  c->add_option("--set", o->run.overrides, "Override a config value: /json/pointer=value");
  c->add_option("--threads", o->threads, "OpenMP threads (default: all cores)")
      ->check(common::positive());
  c->add_flag("--force", o->run.force,
              "Replace an earlier forecast folder (only one of ours; removed after the new run)");
  c->add_flag("--no-pictures", o->no_pictures, "Write no maps and no video");
  c->add_option("--shard", o->shard,
                "Run only shard I of N of the ensemble's members (m - 1 mod N = I) into --out's "
                "ensemble_shard_I_of_N.json; default: the Slurm array task, if any");
  c->add_option("--members-from", o->run.members_from,
                "Take the ensemble's members from the shards' files in this folder");
  c->footer(
      "Exit code: 0 on success; 1 when the run failed; 2 for bad input (a config key, an unknown "
      "oil, a negative rate, a release or watch point outside the reach, a series that does not "
      "cover the forecast, a refused --out); 130 when interrupted. Nothing is written unless the "
      "run finishes.");
  return {c, [o, context] {
            context.catch_stop_signals();
            farfield::ForecastRunOptions run = o->run;
            run.threads = use_threads(o->threads);
            run.stop = context.stop;
            run.log = &std::cerr;
            run.terminal = isatty(STDERR_FILENO) != 0;
            run.pictures = !o->no_pictures;
            if (!o->shard.empty())
              run.shard = common::parse_array_task(o->shard, "--shard");
            else
              run.shard = common::slurm_array_task();
            // A near field first: its oil becomes the far field's as it leaves the box.
            const farfield::ForecastConfig config =
                farfield::load_forecast_config(run.config_file, run.overrides);
            if (config.near_field) {
              // The far field's own input first, so that a bad key is said before the near
              // field's minutes of SPH, not after.
              farfield::build_forecast(config, run.config_file);
              const farfield::NearFieldConfig& n = *config.near_field;
              const sph::NearFieldHandover near =
                  n.run.empty()
                      ? sph::run_near_field_handover(
                            n.scene, n.set,
                            {config.flow.reach_run, run.config_file, "/near_field/scene"}, run.stop,
                            run.log, run.terminal)
                      : sph::near_field_handover_from_run(
                            n.run, {config.flow.reach_run, run.config_file, "/near_field/run"},
                            run.log, run.terminal);
              run.handover = sim::far_field_parcels(near.parcels);
              run.handover_summary = near.summary;
            }
            const nlohmann::json summary = farfield::run_forecast(run);
            if (run.shard) {
              std::cout << "shard " << run.shard->index << "/" << run.shard->count << ": ran "
                        << summary["members_run"].size() << " members into " << summary["file"]
                        << " (then, with the same --config and --set: spill-sim forecast --config "
                        << run.config_file << " --members-from " << run.out_dir << " --out DIR)\n";
              return 0;
            }
            if (run.pictures) sph::encode_animation(run.out_dir, "map", 0, 4, &std::cerr);
            // A Ctrl-C while ffmpeg ran stopped it (its partial video removed): the folder is
            // whole but for the video, and the exit says it was interrupted.
            if (run.stop && run.stop->load())
              throw common::Interrupted("interrupted while encoding " + run.out_dir +
                                        "/map.mp4: the forecast is written, the video is not");
            const auto& last = summary["outputs"].back();
            std::cout << "wrote " << run.out_dir << ": " << summary["elements"] << " elements, "
                      << summary["released_m3"] << " m3 released, t = " << summary["end_time_s"]
                      << " s; leading edge " << last["leading_edge_km"] << " km, "
                      << last["budget_fraction"]["evaporated"] << " evaporated, "
                      << last["budget_fraction"]["stranded"] << " stranded\n";
            return 0;
          }};
}

Command add_forecast_doc_command(CLI::App& app, const CommandContext&) {
  auto* c = app.add_subcommand(
      "forecast-doc",
      "Print every key of a forecast config as a Markdown table (docs/far_field_reference.md)");
  return {c, [] {
            std::cout << farfield::forecast_reference_markdown();
            return 0;
          }};
}

Command add_forecast_bench_command(CLI::App& app, const CommandContext&) {
  auto elements = std::make_shared<std::vector<long>>(std::vector<long>{10000, 100000});
  auto hours = std::make_shared<double>(24);
  auto step = std::make_shared<double>(60);
  auto threads = std::make_shared<int>(0);
  auto* c = app.add_subcommand("forecast-bench",
                               "Time the far field's elements weathering and drifting; print JSON");
  c->add_option("--elements", *elements, "Element counts to time (default 10000 100000)");
  c->add_option("--hours", *hours, "Simulated hours per count (default 24)")
      ->check(common::positive());
  c->add_option("--step", *step, "Time step in seconds (default 60)")->check(common::positive());
  c->add_option("--threads", *threads, "OpenMP threads (default: all cores)")
      ->check(common::positive());
  return {c, [elements, hours, step, threads] {
            const int used = use_threads(*threads);
            const nlohmann::json out = {
                {"benchmark", "far field (farfield/far_field_benchmark.h)"},
                {"machine", sph::machine_description(used)},
                {"rows", farfield::benchmark_far_field(*elements, *hours, *step)}};
            std::cout << out.dump(2) << "\n";
            return 0;
          }};
}

}  // namespace sim
