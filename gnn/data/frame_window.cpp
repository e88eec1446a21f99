#include "gnn/data/frame_window.h"

namespace gnn {

torch::Tensor launched_history(const Trajectory& t, int64_t frame, int64_t particle,
                               double frame_dt) {
  auto x = t.position[frame][particle];
  auto step = t.velocity[frame][particle] * float(frame_dt);
  auto back = torch::arange(kWindow - 1, -1, -1, torch::kFloat32).unsqueeze(1);  // 5 .. 0
  return x.unsqueeze(0) - back * step.unsqueeze(0);
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
