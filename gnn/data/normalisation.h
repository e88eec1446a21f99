#pragma once
// Velocity and acceleration statistics (per frame, over fluid particles of the training split,
// from metadata.json). The standard deviations used for normalising are widened by the training
// noise, sqrt(std^2 + noise_std^2), so inputs keep unit scale when noise dominates small
// components. Stored in every checkpoint, so a model is always used with its own statistics.

#include <torch/torch.h>

#include "gnn/data/dataset.h"

namespace gnn {

struct Normalisation {
  torch::Tensor vel_mean, vel_std, acc_mean, acc_std;  // [3] float32, std already widened

  static Normalisation from_metadata(const DatasetMetadata& m, double noise_std) {
    auto widen = [&](const torch::Tensor& s) { return torch::sqrt(s * s + noise_std * noise_std); };
    return {m.vel_mean.clone(), widen(m.vel_std), m.acc_mean.clone(), widen(m.acc_std)};
  }
};

}  // namespace gnn
