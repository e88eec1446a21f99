#include "sph/generation/trajectory_simulation.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <iostream>

#include "common/progress.h"
#include "sph/core/config.h"
#include "sph/core/floating_point.h"
#include "sph/generation/moments.h"
#include "sph/generation/trajectory_plan.h"
#include "sph/simulation/frame_loop.h"
#include "sph/simulation/simulation.h"

namespace sph {

namespace {

// Running moments of the recorded frames' velocities and accelerations, the sums behind the
// normalisation statistics: velocity x_t - x_(t-1) and acceleration x_(t+1) - 2 x_t + x_(t-1), in
// frame units, over particles active in all the frames involved.
class FrameMoments {
 public:
  void add_frame(const Simulation& sim) {
    const FluidParticles& f = sim.fluid();
    std::vector<std::uint8_t> active(f.size(), 0);
    for (Index i = 0; i < f.active_count(); ++i) active[f.id[i]] = 1;
    std::vector<Vec3> position = sim.in_id_order(f.position);
    for (size_t i = 0; i < position.size(); ++i) {
      if (!previous_.empty() && active[i] && active_previous_[i])
        velocity.add((position[i] - previous_[i]).cast<double>());
      if (!before_.empty() && active[i] && active_previous_[i] && active_before_[i])
        acceleration.add((position[i] - 2 * previous_[i] + before_[i]).cast<double>());
    }
    before_ = std::move(previous_);
    active_before_ = std::move(active_previous_);
    previous_ = std::move(position);
    active_previous_ = std::move(active);
  }
  Moments velocity, acceleration;

 private:
  // Positions and activity of the last two recorded frames, in identity order.
  std::vector<Vec3> before_, previous_;
  std::vector<std::uint8_t> active_before_, active_previous_;
};

}  // namespace

nlohmann::json simulate_trajectory(const GenerateOptions& options, const TrajectoryPlan& plan,
                                   TrajectorySink& sink) {
  const LoadedScene scene = trajectory_scene(options, plan.parameters);
  const SceneConfig& c = scene.config;
  const FlushSubnormalsScope flushed;
  Simulation sim(c);
  const double frame_dt = shortest_decimal(c.output.frame_dt);
  const int scene_frames = int(std::llround(double(c.end_time) / frame_dt));
  double warm_up = options.warm_up;
  if (warm_up < 0) {
    warm_up = 0;
    for (size_t k = 0; k < c.leaks.size(); ++k)
      warm_up = k == 0 ? double(c.leaks[k].start) : std::min(warm_up, double(c.leaks[k].start));
  }
  const int first = int(std::llround(warm_up / frame_dt));
  const int last = options.frames > 0 ? first + options.frames - 1 : scene_frames;
  if (first >= scene_frames || last > scene_frames)
    throw ConfigError(scene.file, "/end_time",
                      "the scene ends at " + std::to_string(c.end_time) + " s; a warm-up of " +
                          std::to_string(warm_up) + " s and " + std::to_string(last - first) +
                          " frames need " + std::to_string(double(last) * frame_dt) + " s");

  sink.begin(sim, plan);
  common::ProgressReporter progress(options.log ? *options.log : std::cerr, false, last,
                                    "trajectory " + std::to_string(plan.index + 1) + "/" +
                                        std::to_string(options.trajectories) + " (" +
                                        split_name(plan.split) + ")");
  FrameMoments moments;
  auto record = [&]() {
    sink.record(sim);
    moments.add_frame(sim);
  };
  // The OpenMP threads the simulation had: LibTorch's first operation (a sink's) once dropped
  // them to one.
  int threads = omp_get_max_threads();
  // Wall time of simulating the recorded frames (not the warm-up): what a learned simulator
  // that rolls the same frames forward is compared against.
  double recorded_wall_s = 0;
  if (first == 0) record();  // the state at the first recorded frame
  FrameLoop loop;
  loop.last = last;
  loop.frame_dt = frame_dt;
  loop.stop = options.stop;
  loop.interrupted_note = sink.interrupted_note(plan);
  loop.progress = options.log ? &progress : nullptr;
  run_frames(sim, loop, [&](int frame, const FrameStats&, double simulated_s) {
    if (frame == first) record();  // after the warm-up
    threads = std::min(threads, omp_get_max_threads());
    if (frame <= first) return;
    recorded_wall_s += simulated_s;
    record();
  });
  if (options.log) progress.finish(std::to_string(sim.steps()) + " steps");
  return {{"index", plan.index},
          {"split", split_name(plan.split)},
          {"parameters", plan.parameters},
          {"particles", sim.fluid().size()},
          {"frames", last - first + 1},
          {"first_frame_time", double(first) * frame_dt},
          {"sph_wall_s", recorded_wall_s},
          {"sph_seconds_per_frame", last > first ? recorded_wall_s / (last - first) : 0.0},
          {"simulation_threads", threads},
          {"velocity_moments", moments.velocity.to_json()},
          {"acceleration_moments", moments.acceleration.to_json()}};
}

}  // namespace sph
