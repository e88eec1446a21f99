// River reaches: after a warm-up the flow through river_small.json is steady at the inflow speed.

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "sph/scene.h"
#include "sph/simulation.h"

namespace sph {
namespace {

const std::string kScenes = std::string(SPILL_SOURCE_DIR) + "/configs/scenes/";

// Mean velocity along the river of the active water between 0.5 m downstream of the inflow and
// 0.5 m upstream of the outflow.
double mean_reach_velocity(const FluidParticles& f, Real from, Real to) {
  double sum = 0;
  long n = 0;
  for (Index i = 0; i < f.active_count(); ++i)
    if (f.position[i].x() > from && f.position[i].x() < to) {
      sum += double(f.velocity[i].x());
      ++n;
    }
  return n ? sum / double(n) : 0;
}

// Steady flow: after 3 s of warm-up, the mean velocity in the reach stays within 10 % of the
// inflow speed and the amount of water in the scene changes by less than 3 % over 2 s.
TEST(River, SmallReachFlowsSteadilyAtTheInflowSpeed) {
  const LoadedScene scene = load_scene(kScenes + "river_small.json", {"/end_time=5"});
  const FlowConfig& flow = *scene.config.flow;
  Simulation sim(scene.config);
  const double frame_dt = double(scene.config.output.frame_dt);
  const Real from = flow.inflow_x + Real(0.5), to = flow.outflow_x - Real(0.5);
  const int warm_up_frames = int(std::lround(3 / frame_dt)),
            frames = int(std::lround(5 / frame_dt));
  for (int frame = 1; frame <= warm_up_frames; ++frame) sim.advance_to(frame * frame_dt, frame);
  const Index water_after_warm_up = sim.fluid().active_count();
  double worst = 0, mean = 0;
  int samples = 0;
  for (int frame = warm_up_frames + 1; frame <= frames; ++frame) {
    sim.advance_to(frame * frame_dt, frame);
    const double u = mean_reach_velocity(sim.fluid(), from, to);
    worst = std::max(worst, std::abs(u / double(flow.speed) - 1));
    mean += u;
    ++samples;
  }
  mean /= samples;
  const double change = double(sim.fluid().active_count()) / double(water_after_warm_up) - 1;
  std::cout << "mean velocity in the reach over 3-5 s: " << mean << " m/s (inflow " << flow.speed
            << "), worst frame off by " << 100 * worst << " %; particles " << water_after_warm_up
            << " -> " << sim.fluid().active_count() << "; emitted " << sim.flow()->emitted()
            << ", retired " << sim.flow()->retired() << "\n";
  EXPECT_LT(worst, 0.1);
  EXPECT_LT(std::abs(change), 0.03);
}

}  // namespace
}  // namespace sph
