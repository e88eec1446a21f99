#include "gnn/data/frame_window.h"

namespace gnn {

torch::Tensor launched_histories(const torch::Tensor& position, const torch::Tensor& velocity,
                                 double frame_dt) {
  auto back = torch::arange(kWindow - 1, -1, -1, torch::kFloat32).view({1, kWindow, 1});  // 5..0
  return position.unsqueeze(1) - back * (velocity * float(frame_dt)).unsqueeze(1);
}

torch::Tensor launched_history(const Trajectory& t, int64_t frame, int64_t particle,
                               double frame_dt) {
  return launched_histories(t.position[frame][particle].unsqueeze(0),
                            t.velocity[frame][particle].unsqueeze(0), frame_dt)[0];
}

torch::Tensor position_history(const Trajectory& t, int64_t frame, const torch::Tensor& ids,
                               double frame_dt) {
  const int64_t n = ids.size(0);
  auto out = torch::empty({n, kWindow, 3});
  auto ids_a = ids.accessor<int64_t, 1>();
  auto active = t.active.accessor<bool, 2>();
  auto pos = t.position.accessor<float, 3>();
  auto vel = t.velocity.accessor<float, 3>();
  auto o = out.accessor<float, 3>();
  for (int64_t i = 0; i < n; ++i) {
    const int64_t p = ids_a[i];
    // First frame of the run of active frames that ends at `frame` (within the window).
    int64_t first = frame;
    while (first > frame - (kWindow - 1) && first > 0 && active[first - 1][p]) --first;
    for (int64_t k = 0; k < kWindow; ++k) {
      const int64_t f = frame - (kWindow - 1) + k;
      for (int d = 0; d < 3; ++d)
        o[i][k][d] = f >= first
                         ? pos[f][p][d]
                         : pos[first][p][d] - float(first - f) * vel[first][p][d] * float(frame_dt);
    }
  }
  return out;
}

}  // namespace gnn
