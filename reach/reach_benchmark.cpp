#include "reach/reach_benchmark.h"

#include <chrono>
#include <cmath>

#include "reach/shallow_water.h"

namespace reach {

nlohmann::json benchmark_reach(const std::vector<long>& cell_counts, int steps, int warm_up) {
  nlohmann::json rows = nlohmann::json::array();
  for (long cells : cell_counts) {
    Grid g;
    g.ny = std::max(4, int(std::lround(std::sqrt(double(cells) / 25.0))));
    g.nx = 25 * g.ny;
    g.dx = g.dy = 2.0;
    const double width = g.ny * g.dy, slope = 1e-3, n = 0.03;
    Field bed(g.cells());
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i) {
        const double across = (g.y(j) - 0.5 * width) / width;        // -1/2 .. 1/2
        bed[g.at(i, j)] = -slope * g.x(i) + 12.0 * across * across;  // banks 3 m above the centre
      }
    ShallowWaterSolver s(g, bed, {n});
    // Still water 2 m deep at the centre everywhere along the valley: the level falls with the
    // bed, so it starts moving at once.
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i) {
        const size_t c = g.at(i, j);
        s.state().h[c] = std::max(0.0, 2.0 - 12.0 * std::pow((g.y(j) - 0.5 * width) / width, 2));
      }
    // About the normal discharge of that section.
    double q = 0;
    for (int j = 0; j < g.ny; ++j) {
      const double h = s.state().h[g.at(0, j)];
      q += h > 0 ? std::pow(h, 5.0 / 3.0) * std::sqrt(slope) / n * g.dy : 0.0;
    }
    s.add_inflow({{Side::kWest, 0, g.ny - 1}, Hydrograph(q), "upstream", {}});
    OutflowBoundary out;
    out.section = {Side::kEast, 0, g.ny - 1};
    out.kind = OutflowKind::kNormalDepth;
    out.slope = slope;
    s.add_outflow(out);
    for (int k = 0; k < warm_up; ++k) s.step(s.stable_dt());
    const double t0 = s.time();
    const auto start = std::chrono::steady_clock::now();
    for (int k = 0; k < steps; ++k) s.step(s.stable_dt());
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    long wet = 0;
    for (double h : s.state().h) wet += h > 1e-6;
    const double dt = (s.time() - t0) / steps;
    const double rate = double(g.cells()) * steps / wall;
    rows.push_back({{"cells", long(g.cells())},
                    {"nx", g.nx},
                    {"ny", g.ny},
                    {"wet_share", double(wet) / double(g.cells())},
                    {"discharge_m3_s", q},
                    {"dt_s", dt},
                    {"steps", steps},
                    {"wall_s", wall},
                    {"cell_updates_per_s", rate},
                    {"wall_s_per_simulated_hour", 3600.0 / dt * double(g.cells()) / rate}});
  }
  return rows;
}

}  // namespace reach
