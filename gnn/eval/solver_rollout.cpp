#include "gnn/eval/solver_rollout.h"

#include <chrono>
#include <stdexcept>
#include <string>

#include "gnn/eval/scene_rollout.h"

namespace gnn {

RolloutResult solver_rollout(const Trajectory& t, int64_t first_frame, int64_t frames,
                             double frame_dt, double jitter, uint64_t seed,
                             const std::function<void(int64_t)>& on_frame) {
  if (first_frame < 0 || frames < 1 || first_frame + frames >= t.frames())
    throw std::invalid_argument(t.source + ": cannot run " + std::to_string(frames) +
                                " frames from frame " + std::to_string(first_frame) + " of " +
                                std::to_string(t.frames()));
  if (!(jitter >= 0)) throw std::invalid_argument("solver rollout: jitter must be >= 0");
  auto sim = simulation_at_frame(t, first_frame, frame_dt, [&](sph::RecordedFrame& f) {
    jitter_active_positions(f, jitter, seed);
  });
  RolloutResult out;
  out.first_frame = first_frame;
  out.position = torch::empty({frames + 1, t.particles(), 3});
  out.active = torch::empty({frames + 1, t.particles()}, torch::kBool);
  out.oil_fraction = torch::empty({frames + 1, t.particles()});
  out.position[0] = t.position[first_frame];
  out.active[0] = t.active[first_frame];
  out.oil_fraction[0] = t.oil_fraction[first_frame];
  const double start_time = sim->time();
  for (int64_t k = 0; k < frames; ++k) {
    const auto start = std::chrono::steady_clock::now();
    sim->advance_to(start_time + double(k + 1) * frame_dt, int(first_frame + k + 1));
    const IdentityFrame f = identity_frame(*sim);
    out.position[k + 1] = f.position;
    out.active[k + 1] = f.active;
    out.oil_fraction[k + 1] = f.oil_fraction;
    out.frame_seconds.push_back(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    if (on_frame) on_frame(k + 1);
  }
  return out;
}

}  // namespace gnn
