#pragma once
// How sure a mean over a handful of trajectories is: the percentile bootstrap interval (Efron &
// Tibshirani 1993), resampling the values with replacement. With 8 or 16 trajectories a figure's
// interval is often wider than the gap between two models; a gap inside it decides nothing.

#include <cstdint>
#include <vector>

namespace gnn {

struct Interval {
  double low = 0, high = 0;
};

// The central `level` (e.g. 0.9) interval of the mean of `values` over `resamples` resamples
// drawn with a generator seeded by `seed` (deterministic). One value gives [v, v]. Throws
// std::invalid_argument for no values, a level outside (0, 1) or fewer than 100 resamples.
Interval bootstrap_mean_interval(const std::vector<double>& values, double level = 0.9,
                                 int resamples = 2000, uint64_t seed = 1);

}  // namespace gnn
