#include "gnn/training/noise.h"

#include <cmath>

namespace gnn {

torch::Tensor random_walk_noise(const torch::Tensor& history, double noise_std,
                                torch::Generator& generator) {
  if (noise_std <= 0) return history;
  const int64_t n = history.size(0), steps = history.size(1) - 1;
  auto increments = at::normal(0.0, noise_std / std::sqrt(double(steps)), {n, steps, 3}, generator);
  auto velocity_noise = increments.cumsum(1);
  auto position_noise = torch::cat({torch::zeros({n, 1, 3}), velocity_noise.cumsum(1)}, 1);
  return history + position_noise;
}

}  // namespace gnn
