#include "gnn/eval/bootstrap.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

namespace gnn {

Interval bootstrap_mean_interval(const std::vector<double>& values, double level, int resamples,
                                 uint64_t seed) {
  if (values.empty()) throw std::invalid_argument("bootstrap: no values");
  if (!(level > 0 && level < 1)) throw std::invalid_argument("bootstrap: level outside (0, 1)");
  if (resamples < 100) throw std::invalid_argument("bootstrap: fewer than 100 resamples");
  if (values.size() == 1) return {values[0], values[0]};
  std::mt19937_64 random(seed);
  std::uniform_int_distribution<size_t> pick(0, values.size() - 1);
  std::vector<double> means(static_cast<size_t>(resamples));
  for (double& m : means) {
    double sum = 0;
    for (size_t k = 0; k < values.size(); ++k) sum += values[pick(random)];
    m = sum / double(values.size());
  }
  std::sort(means.begin(), means.end());
  // The order statistics at the two tails, by linear interpolation between neighbours.
  const auto quantile = [&](double q) {
    const double at = q * double(means.size() - 1);
    const size_t below = size_t(std::floor(at));
    const size_t above = std::min(below + 1, means.size() - 1);
    return means[below] + (at - double(below)) * (means[above] - means[below]);
  };
  return {quantile((1 - level) / 2), quantile((1 + level) / 2)};
}

}  // namespace gnn
