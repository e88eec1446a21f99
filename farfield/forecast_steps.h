#pragma once
// The forecast's step loop, the same for the forecast and for each member of its ensemble: the
// near field's oil handed over as it comes, a step, the watch points' arrivals, and a call after
// every step that says whether it is an output time (time 0 is one).

#include <atomic>
#include <functional>
#include <vector>

#include "farfield/forecast_config.h"
#include "farfield/model/far_field_model.h"
#include "farfield/outputs/forecast_metrics.h"

namespace farfield {

// Oil handed over from a near field: `volume` m^3 at map point (x, y) at forecast time t.
struct HandoverParcel {
  double t = 0, x = 0, y = 0, volume = 0, area = 0;
};

// The config's number of steps and the steps between outputs.
struct StepPlan {
  long steps = 0, every = 1;
  explicit StepPlan(const ForecastConfig& c);
  bool is_output(long k) const { return k == 0 || k % every == 0 || k == steps; }
  size_t outputs() const;
};

// Steps `model` to the config's end; `after(k)` runs after step k (and once before the first,
// with k = 0). Returns the volume handed over (m^3). Throws common::Interrupted when `stop` is set.
double step_forecast(FarFieldModel& model, const ForecastConfig& config,
                     const std::vector<HandoverParcel>& parcels, std::vector<WatchPoint>& points,
                     const std::function<void(long k)>& after, const std::atomic<bool>* stop);

}  // namespace farfield
