#include "farfield/forecast_run.h"

#include <chrono>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>

#include "common/checked_file.h"
#include "common/exit_codes.h"
#include "common/output_folder.h"
#include "common/progress.h"
#include "farfield/forecast_ensemble.h"
#include "farfield/forecast_recorder.h"
#include "farfield/outputs/forecast_report.h"

namespace farfield {

namespace fs = std::filesystem;

namespace {

// A shard of the ensemble's members: their tally in out_dir/ensemble_shard_I_of_N.json, written
// whole or not at all, so that an assembling run never reads half a file.
nlohmann::json run_shard(const ForecastRunOptions& o, const ForecastConfig& config,
                         const ForecastSetup& setup) {
  if (!config.ensemble)
    throw ConfigError(o.config_file, "/ensemble",
                      "--shard runs a share of an ensemble's members, but the config has no "
                      "/ensemble");
  const auto& flow = static_cast<const ReachFlow&>(*setup.model.flow);
  ForecastEnsemble ensemble(setup, flow);
  const std::vector<int> members =
      ensemble.run_members(o.handover, o.stop, o.log, o.terminal, *o.shard);
  nlohmann::json shard = {{"config_file", o.config_file},
                          {"config_digest", forecast_digest(config)},
                          {"shard", {o.shard->index, o.shard->count}},
                          {"members_run", members}};
  const fs::path folder = o.out_dir;
  fs::create_directories(folder);
  const fs::path file = folder / shard_file_name(*o.shard);
  nlohmann::json content = shard;
  content["tally"] = ensemble.tally().to_json();
  common::write_file_atomically(file, content.dump() + "\n");
  shard["file"] = file.string();
  return shard;
}

}  // namespace

nlohmann::json run_forecast(const ForecastRunOptions& o) {
  ForecastRunFacts facts;
  facts.wall_start = std::chrono::steady_clock::now();
  facts.config_file = o.config_file;
  facts.threads = o.threads;
  facts.handover_parcels = o.handover.size();
  facts.handover_summary = o.handover_summary;
  const ForecastConfig config = load_forecast_config(o.config_file, o.overrides);
  ForecastSetup setup = build_forecast(config, o.config_file);
  if (config.near_field && o.handover.empty())
    throw ConfigError(o.config_file, "/near_field",
                      "no oil was handed over from the near field (run it with spill-sim "
                      "forecast, which runs the near field first)");
  if (o.shard) return run_shard(o, config, setup);
  if (!o.members_from.empty() && !config.ensemble)
    throw ConfigError(o.config_file, "/ensemble",
                      "--members-from assembles an ensemble's members, but the config has no "
                      "/ensemble");
  common::OutputFolderPolicy policy;
  policy.markers = {"forecast.json"};
  policy.replace = o.force;
  policy.inputs = {fs::path(o.config_file), fs::path(config.flow.reach_run)};
  policy.log = o.log;
  common::OutputFolder folder(o.out_dir, policy);
  const auto& flow = static_cast<const ReachFlow&>(*setup.model.flow);
  ForecastRecorder recorder(folder.staging(), setup, flow, o.pictures, o.stop);
  FarFieldModel model(setup.model);
  std::vector<WatchPoint>& points = setup.watch_points;
  // With an ensemble, the forecast is its member 0, tallied as it steps.
  std::unique_ptr<ForecastEnsemble> ensemble;
  if (config.ensemble) {
    ensemble = std::make_unique<ForecastEnsemble>(setup, flow);
    ensemble->tally().begin_member();
  }

  const StepPlan plan(config);
  common::ProgressReporter progress(o.log ? *o.log : std::cerr, o.terminal, plan.steps, "forecast");
  facts.handed_over_m3 = step_forecast(
      model, config, o.handover, points,
      [&](long k) {
        facts.worst_closure = std::max(facts.worst_closure, model.budget().closure_error());
        if (ensemble) ensemble->tally().after_step(model);
        if (plan.is_output(k)) {
          recorder.record(model, points);
          if (ensemble) ensemble->tally().at_output(model);
        }
        if (o.log && k > 0) {
          std::ostringstream detail;
          detail << model.elements().size() << " elements, t = " << std::lround(model.time())
                 << " s";
          progress.update(k, detail.str());
        }
      },
      o.stop);
  if (o.log) progress.finish(std::to_string(model.elements().size()) + " elements");

  ShoreProbability shore;
  if (ensemble) {
    ensemble->tally().end_member(points);
    if (o.members_from.empty())
      ensemble->run_members(o.handover, o.stop, o.log, o.terminal);
    else
      ensemble->add_shards(o.members_from, forecast_digest(config));
    const std::vector<double> times = recorder.output_times();
    const std::vector<std::string> clocks = recorder.output_clocks();
    facts.ensemble = ensemble->summary(times, clocks);
    shore = ensemble->shore_probability(times.back(), clocks.back());
    facts.shore_probability = &shore;
    ensemble->write_files(folder.staging(), times, clocks, o.pictures);
  }
  const nlohmann::json summary = recorder.finish(model, points, facts);
  write_forecast_report(folder.staging(), summary);
  folder.commit();
  return summary;
}

}  // namespace farfield
