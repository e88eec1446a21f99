#include "farfield/forecast_run.h"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "common/exit_codes.h"
#include "common/output_folder.h"
#include "common/progress.h"
#include "farfield/forecast_recorder.h"

namespace farfield {

namespace fs = std::filesystem;

namespace {

// The near field's oil that leaves its box before `until` joins the far field, each parcel as
// several elements so that the mixing spreads it as a cloud; returns the volume added (m^3).
double add_handed_over(FarFieldModel& model, const std::vector<HandoverParcel>& parcels,
                       size_t& next, double until, int elements_per_parcel, double oil_density) {
  double volume = 0;
  for (; next < parcels.size() && parcels[next].t < until; ++next) {
    const HandoverParcel& p = parcels[next];
    for (int k = 0; k < elements_per_parcel; ++k)
      model.add_element(p.x, p.y, p.volume / elements_per_parcel * oil_density,
                        p.area / elements_per_parcel);
    volume += p.volume;
  }
  return volume;
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

  const long steps = long(std::ceil(config.end_time / config.time_step - 1e-9));
  const long every = std::max(1L, long(std::lround(config.output_every / config.time_step)));
  const int per_parcel = config.near_field ? config.near_field->elements_per_parcel : 1;
  common::ProgressReporter progress(o.log ? *o.log : std::cerr, o.terminal, steps, "forecast");
  recorder.record(model, points);
  size_t next_parcel = 0;
  for (long k = 1; k <= steps; ++k) {
    if (o.stop && o.stop->load()) throw common::Interrupted("forecast interrupted");
    const double dt = std::min(config.time_step, config.end_time - model.time());
    facts.handed_over_m3 += add_handed_over(model, o.handover, next_parcel, model.time() + dt,
                                            per_parcel, setup.model.oil.density);
    model.step(dt);
    update_arrivals(model, points);
    facts.worst_closure = std::max(facts.worst_closure, model.budget().closure_error());
    if (k % every == 0 || k == steps) recorder.record(model, points);
    if (o.log) {
      std::ostringstream detail;
      detail << model.elements().size() << " elements, t = " << std::lround(model.time()) << " s";
      progress.update(k, detail.str());
    }
  }
  if (o.log) progress.finish(std::to_string(model.elements().size()) + " elements");
  const nlohmann::json summary = recorder.finish(model, points, facts);
  folder.commit();
  return summary;
}

}  // namespace farfield
