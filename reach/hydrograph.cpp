#include "reach/hydrograph.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace reach {

Hydrograph::Hydrograph(std::vector<std::pair<double, double>> points) : points_(std::move(points)) {
  if (points_.empty()) throw std::invalid_argument("a hydrograph needs at least one point");
  for (size_t k = 1; k < points_.size(); ++k)
    if (!(points_[k].first > points_[k - 1].first))
      throw std::invalid_argument("hydrograph times must increase strictly: point " +
                                  std::to_string(k) + " at " + std::to_string(points_[k].first) +
                                  " s follows " + std::to_string(points_[k - 1].first) + " s");
}

double Hydrograph::at(double t) const {
  if (t <= points_.front().first) return points_.front().second;
  if (t >= points_.back().first) return points_.back().second;
  const auto next = std::upper_bound(points_.begin(), points_.end(), t,
                                     [](double time, const auto& p) { return time < p.first; });
  const auto& [t1, v1] = *next;
  const auto& [t0, v0] = *(next - 1);
  return v0 + (v1 - v0) * (t - t0) / (t1 - t0);
}

double Hydrograph::peak() const {
  double peak = points_.front().second;
  for (const auto& p : points_) peak = std::max(peak, p.second);
  return peak;
}

double Hydrograph::integral(double a, double b) const {
  if (!(b > a)) return 0;
  // Trapezoids between a, the points inside (a, b) and b: exact for a piecewise-linear series.
  double sum = 0, t_prev = a, v_prev = at(a);
  for (const auto& [t, v] : points_) {
    if (t <= a || t >= b) continue;
    sum += 0.5 * (v_prev + v) * (t - t_prev);
    t_prev = t;
    v_prev = v;
  }
  return sum + 0.5 * (v_prev + at(b)) * (b - t_prev);
}

}  // namespace reach
