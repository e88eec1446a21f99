#pragma once
// Velocity and acceleration statistics (per frame, over fluid particles of the training split,
// from metadata.json), and the spread of the oil fraction's change per frame. The standard
// deviations used for normalising are widened by the training noise, sqrt(std^2 + noise_std^2),
// so inputs keep unit scale when noise dominates small components. Stored in every checkpoint, so
// a model is always used with its own statistics.

#include <torch/torch.h>

#include <vector>

#include "gnn/data/dataset.h"

namespace gnn {

// Below this the fraction's change is taken as this: data without exchange between phases (a
// single-phase solver, or none yet) would otherwise divide by zero.
constexpr double kMinFractionChangeStd = 1e-4;

struct Normalisation {
  torch::Tensor vel_mean, vel_std, acc_mean, acc_std;  // [3] float32, std already widened
  torch::Tensor fraction_change_std;                   // [1] float32, at least the floor above

  static Normalisation from_metadata(const DatasetMetadata& m, double noise_std,
                                     double fraction_change_std) {
    auto widen = [&](const torch::Tensor& s) { return torch::sqrt(s * s + noise_std * noise_std); };
    return {m.vel_mean.clone(), widen(m.vel_std), m.acc_mean.clone(), widen(m.acc_std),
            torch::tensor({float(std::max(fraction_change_std, kMinFractionChangeStd))})};
  }
};

// Root mean square of the oil fraction's change per frame over the fluid particles active in
// both frames of every frame pair of `trajectories` (the mean is zero when oil is conserved, so
// no mean is taken off).
inline double oil_fraction_change_rms(const std::vector<Trajectory>& trajectories) {
  double sum = 0, count = 0;
  for (const auto& t : trajectories) {
    const int64_t T = t.frames();
    if (T < 2) continue;
    const auto both = t.active.slice(0, 1) & t.active.slice(0, 0, T - 1);
    const auto change = (t.oil_fraction.slice(0, 1) - t.oil_fraction.slice(0, 0, T - 1))
                            .to(torch::kFloat64)
                            .index({both});
    sum += change.pow(2).sum().item<double>();
    count += double(change.numel());
  }
  return count > 0 ? std::sqrt(sum / count) : 0.0;
}

}  // namespace gnn
