#include "farfield/far_field_benchmark.h"

#include <chrono>
#include <memory>

#include "farfield/flows/channel_flow.h"
#include "farfield/model/far_field_model.h"

namespace farfield {

nlohmann::json benchmark_far_field(const std::vector<long>& element_counts, double hours,
                                   double step) {
  nlohmann::json rows = nlohmann::json::array();
  for (const long n : element_counts) {
    auto flow = std::make_shared<ChannelFlow>();
    flow->length = 1e6;
    flow->width = 2000;
    FarFieldSetup s;
    s.flow = flow;
    s.oil = load_oil("light_crude", SPILL_OIL_LIBRARY, "benchmark", "/oil");
    s.centreline = Centreline({{0.0, 1000.0}, {1e6, 1000.0}});
    s.banks = Banks(s.centreline, 1000, {BankClass{"sand", 0.01, 86400}}, 0, {});
    s.environment.wind_speed = reach::Hydrograph(5.0);
    s.environment.wind_from_deg = reach::Hydrograph(270.0);  // downstream: nothing strands
    ReleaseSpec r;
    r.x0 = r.x1 = 1000;
    r.y0 = r.y1 = 1000;
    r.rate = reach::Hydrograph(100.0);
    r.elements = int(n);
    s.releases = {r};
    FarFieldModel model(s);
    model.step(step);  // the release, untimed
    const long steps = long(hours * 3600 / step);
    const auto start = std::chrono::steady_clock::now();
    for (long k = 0; k < steps; ++k) model.step(step);
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const Budget b = model.budget();
    rows.push_back({{"elements", n},
                    {"steps", steps},
                    {"step_s", step},
                    {"simulated_h", hours},
                    {"wall_s", wall},
                    {"element_steps_per_s", double(n) * double(steps) / wall},
                    {"evaporated_fraction", b.evaporated / b.released},
                    {"floating_fraction_at_end", b.floating / b.released},
                    {"budget_closure_error", b.closure_error()}});
  }
  return rows;
}

}  // namespace farfield
