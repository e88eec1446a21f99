#include "gnn/eval/ensemble_scores.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace gnn {

double fair_crps(const std::vector<double>& members, double observed) {
  if (members.empty()) throw std::invalid_argument("fair_crps: an ensemble needs members");
  if (!std::isfinite(observed))
    throw std::invalid_argument("fair_crps: the observation is not finite");
  std::vector<double> x = members;
  for (double v : x)
    if (!std::isfinite(v)) throw std::invalid_argument("fair_crps: a member is not finite");
  const double k = double(x.size());
  double distance_to_observed = 0;
  for (double v : x) distance_to_observed += std::abs(v - observed);
  if (x.size() == 1) return distance_to_observed;
  // Sum over ordered pairs of |x_i - x_j| in O(K log K): sorted, x_(i) is above i of them and
  // below K - 1 - i.
  std::sort(x.begin(), x.end());
  double pairs = 0;
  for (size_t i = 0; i < x.size(); ++i) pairs += 2 * x[i] * (2 * double(i) - k + 1);
  return distance_to_observed / k - pairs / (2 * k * (k - 1));
}

double fair_brier(int members_with_event, int members, bool happened) {
  if (members < 1) throw std::invalid_argument("fair_brier: an ensemble needs members");
  if (members_with_event < 0 || members_with_event > members)
    throw std::invalid_argument("fair_brier: more members with the event than members");
  const double p = double(members_with_event) / double(members);
  const double o = happened ? 1.0 : 0.0;
  if (members == 1) return (p - o) * (p - o);
  return (p - o) * (p - o) - p * (1 - p) / double(members - 1);
}

}  // namespace gnn
