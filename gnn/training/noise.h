#pragma once
// Training noise of GNS (Sanchez-Gonzalez et al. 2020): a random walk on the input velocities.
// Each of the 5 velocities of a window gets an independent increment of std noise_std / sqrt(5);
// the increments accumulate, so the last velocity is off by noise_std, and positions follow by
// summing the velocities from an unperturbed oldest position. The training target is taken from
// the noisy last position and velocity, so the model learns to steer a noisy state back to the
// true next position.

#include <torch/torch.h>

namespace gnn {

// `history` [n, 6, 3]: returns a noisy copy (the oldest position unchanged).
torch::Tensor random_walk_noise(const torch::Tensor& history, double noise_std,
                                torch::Generator& generator);

// Acceleration (per frame^2) that takes the window's last two positions to `next`:
// next - 2 x_t + x_(t-1).
inline torch::Tensor target_acceleration(const torch::Tensor& history, const torch::Tensor& next) {
  const int64_t last = history.size(1) - 1;
  return next - 2 * history.select(1, last) + history.select(1, last - 1);
}

}  // namespace gnn
