#include "farfield/forecast_run.h"

#include <chrono>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>

#include "common/exit_codes.h"
#include "common/output_folder.h"
#include "common/progress.h"
#include "farfield/forecast_ensemble.h"
#include "farfield/forecast_recorder.h"

namespace farfield {

namespace fs = std::filesystem;

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
    ensemble->run_members(o.handover, o.stop, o.log, o.terminal);
    const std::vector<double> times = recorder.output_times();
    const std::vector<std::string> clocks = recorder.output_clocks();
    facts.ensemble = ensemble->summary(times, clocks);
    shore = ensemble->shore_probability(times.back(), clocks.back());
    facts.shore_probability = &shore;
    ensemble->write_files(folder.staging(), times, clocks, o.pictures);
  }
  const nlohmann::json summary = recorder.finish(model, points, facts);
  folder.commit();
  return summary;
}

}  // namespace farfield
