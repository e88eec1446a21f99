#include "sph/simulation/frame_loop.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "common/stopwatch.h"
#include "sph/core/config.h"

namespace sph {

int frame_count(const SceneConfig& s) {
  return int(std::llround(double(s.end_time) / shortest_decimal(s.output.frame_dt)));
}

std::string frame_detail(const Simulation& sim, const FrameStats& f) {
  std::ostringstream s;
  s.precision(3);
  s << "t=" << sim.time() << "s steps=" << f.steps << " it=" << f.iterations_density << "/"
    << f.iterations_divergence << " err=" << f.density_error_avg * 100 << "%";
  return s.str();
}

FrameLoopTotals run_frames(Simulation& sim, const FrameLoop& loop,
                           const std::function<void(int, const FrameStats&, double)>& on_frame) {
  const auto t0 = std::chrono::steady_clock::now();
  double it_density = 0, it_divergence = 0, density_error = 0;
  long steps = 0;
  for (int frame = loop.first + 1; frame <= loop.last; ++frame) {
    if (loop.stop && loop.stop->load())
      throw RunInterrupted("interrupted at frame " + std::to_string(frame) +
                           (loop.interrupted_note.empty() ? "" : "; " + loop.interrupted_note));
    const auto frame_start = std::chrono::steady_clock::now();
    const FrameStats f = sim.advance_to(double(frame) * loop.frame_dt, frame);
    const double simulated_s = common::seconds_since(frame_start);
    it_density += f.iterations_density * f.steps;
    it_divergence += f.iterations_divergence * f.steps;
    density_error += f.density_error_avg * f.steps;
    steps += f.steps;
    on_frame(frame, f, simulated_s);
    if (loop.progress) loop.progress->update(frame, frame_detail(sim, f));
  }
  FrameLoopTotals totals;
  totals.wall_s = common::seconds_since(t0);
  totals.iterations_density = it_density / double(std::max(1L, steps));
  totals.iterations_divergence = it_divergence / double(std::max(1L, steps));
  totals.density_error_avg = density_error / double(std::max(1L, steps));
  return totals;
}

}  // namespace sph
