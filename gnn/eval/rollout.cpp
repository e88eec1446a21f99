#include "gnn/eval/rollout.h"

#include <chrono>
#include <stdexcept>

#include "gnn/data/frame_window.h"

namespace gnn {

RolloutResult rollout(LearnedSimulator& simulator, const Trajectory& t, int64_t first_frame,
                      int64_t frames, double frame_dt, const std::function<void(int64_t)>& on_frame,
                      const FrameCorrection& correct) {
  if (first_frame < 0 || frames < 1 || first_frame + frames >= t.frames())
    throw std::invalid_argument(t.source + ": cannot roll out " + std::to_string(frames) +
                                " frames from frame " + std::to_string(first_frame) + " of " +
                                std::to_string(t.frames()));
  torch::NoGradGuard no_grad;
  const int64_t N = t.particles();
  RolloutResult out;
  out.first_frame = first_frame;
  out.position = torch::empty({frames + 1, N, 3});
  out.active = torch::empty({frames + 1, N}, torch::kBool);
  out.oil_fraction = torch::empty({frames + 1, N});
  auto history = torch::zeros({N, kWindow, 3});
  auto fraction = t.oil_fraction[first_frame].clone();
  auto active = t.active[first_frame].clone();
  auto ids = active_ids(t, first_frame);
  history.index_copy_(0, ids, position_history(t, first_frame, ids, frame_dt));
  out.position[0] = t.position[first_frame];
  out.active[0] = active;
  out.oil_fraction[0] = fraction;
  for (int64_t k = 0; k < frames; ++k) {
    const auto start = std::chrono::steady_clock::now();
    const int64_t frame = first_frame + k;
    ids = active.nonzero().view(-1);
    auto window = history.index_select(0, ids);
    FrameNodes nodes{window, fraction.index_select(0, ids), t.material, t.boundary};
    NextState next = simulator.next_state(nodes);
    // Named here, with the trajectory and the frame: later it would surface as a radius graph
    // of non-finite positions, naming neither.
    if (!torch::isfinite(next.position).all().item<bool>())
      throw std::runtime_error(t.source + ": the model diverged at rollout frame " +
                               std::to_string(k + 1) + " (recorded frame " +
                               std::to_string(frame + 1) + "): a predicted position is not finite");
    if (correct) correct(next.position, next.oil_fraction);
    history.index_copy_(0, ids, torch::cat({window.slice(1, 1), next.position.unsqueeze(1)}, 1));
    fraction.index_copy_(0, ids, next.oil_fraction);
    // The recorded schedule of the next frame: retire, then activate.
    auto recorded = t.active[frame + 1];
    active.logical_and_(recorded);
    auto launched = (recorded & ~active).nonzero().view(-1);
    for (int64_t i = 0; i < launched.size(0); ++i) {
      const int64_t p = launched[i].item<int64_t>();
      history[p] = launched_history(t, frame + 1, p, frame_dt);
    }
    fraction.index_copy_(0, launched, t.oil_fraction[frame + 1].index_select(0, launched));
    active.logical_or_(recorded);
    out.position[k + 1] =
        torch::where(active.unsqueeze(1), history.select(1, kWindow - 1), t.position[frame + 1]);
    out.active[k + 1] = active;
    out.oil_fraction[k + 1] = torch::where(active, fraction, t.oil_fraction[frame + 1]);
    out.frame_seconds.push_back(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    if (on_frame) on_frame(k + 1);
  }
  return out;
}

double one_step_position_mse(LearnedSimulator& simulator, const Trajectory& t,
                             const std::vector<int64_t>& frames, double frame_dt) {
  torch::NoGradGuard no_grad;
  double sum = 0;
  int64_t count = 0;
  for (int64_t frame : frames) {
    auto ids = active_ids(t, frame);
    FrameNodes nodes{position_history(t, frame, ids, frame_dt),
                     t.oil_fraction[frame].index_select(0, ids), t.material, t.boundary};
    auto next = simulator.next_position(nodes);
    auto truth = t.position[frame + 1].index_select(0, ids);
    auto keep = t.active[frame + 1].index_select(0, ids);
    auto error = (next - truth).pow(2).index({keep});
    sum += error.sum().item<double>();
    count += error.numel();
  }
  return count ? sum / double(count) : 0.0;
}

}  // namespace gnn
