#include "farfield/forecast_steps.h"

#include <algorithm>
#include <cmath>

#include "common/exit_codes.h"

namespace farfield {

StepPlan::StepPlan(const ForecastConfig& c)
    : steps(long(std::ceil(c.end_time / c.time_step - 1e-9))),
      every(std::max(1L, long(std::lround(c.output_every / c.time_step)))) {}

size_t StepPlan::outputs() const {
  size_t n = 0;
  for (long k = 0; k <= steps; ++k) n += is_output(k) ? 1 : 0;
  return n;
}

double step_forecast(FarFieldModel& model, const ForecastConfig& config,
                     const std::vector<HandoverParcel>& parcels, std::vector<WatchPoint>& points,
                     const std::function<void(long k)>& after, const std::atomic<bool>* stop) {
  const StepPlan plan(config);
  // Each handed-over parcel as several elements of one slick, so that the mixing spreads it as a
  // cloud.
  const int per_parcel = config.near_field ? config.near_field->elements_per_parcel : 1;
  const double density = model.setup().oil.density;
  double handed_over = 0;
  size_t next = 0;
  after(0);
  for (long k = 1; k <= plan.steps; ++k) {
    if (stop && stop->load()) throw common::Interrupted("forecast interrupted");
    const double dt = std::min(config.time_step, config.end_time - model.time());
    for (; next < parcels.size() && parcels[next].t < model.time() + dt; ++next) {
      const HandoverParcel& p = parcels[next];
      model.add_parcel(p.x, p.y, p.volume * density, p.area, per_parcel);
      handed_over += p.volume;
    }
    model.step(dt);
    update_arrivals(model, points);
    after(k);
  }
  return handed_over;
}

}  // namespace farfield
