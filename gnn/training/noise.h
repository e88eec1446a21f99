#pragma once
// Training noise of GNS (Sanchez-Gonzalez et al. 2020): a random walk on the input velocities.
// Each of the 5 velocities of a window gets an independent increment of std noise_std / sqrt(5);
// the increments accumulate, so the last velocity is off by noise_std, and positions follow by
// summing the velocities from an unperturbed oldest position. The training target is GNS's
// (noisy_target_acceleration): the next position is shifted by the noise of the last input
// position, so the model learns to correct the velocity noise, not to pull the position back.

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

// GNS's target under input noise (learned_simulator.py of Sanchez-Gonzalez et al.): the
// acceleration that takes the noisy window's last two positions to `next` shifted by the noise
// of the last position, next + (noisy_t - clean_t). Its velocity is then the true next velocity
// next - clean_t: the noise in the velocity is corrected, the offset in the position is kept
// (correcting it too would teach the model to jump by the noise at every frame).
inline torch::Tensor noisy_target_acceleration(const torch::Tensor& clean,
                                               const torch::Tensor& noisy,
                                               const torch::Tensor& next) {
  const int64_t last = clean.size(1) - 1;
  return target_acceleration(noisy, next + (noisy.select(1, last) - clean.select(1, last)));
}

}  // namespace gnn
