#pragma once
// A discharge (or stage) as a function of time, piecewise linear between given points and held
// constant before the first and after the last: what an upstream boundary is given.

#include <utility>
#include <vector>

namespace reach {

class Hydrograph {
 public:
  // A constant value.
  explicit Hydrograph(double value = 0) : points_{{0.0, value}} {}
  // (time s, value) points in strictly increasing time; throws std::invalid_argument otherwise.
  explicit Hydrograph(std::vector<std::pair<double, double>> points);

  double at(double t) const;
  double peak() const;
  // The integral over [a, b] (exact for the piecewise-linear series; 0 when b <= a).
  double integral(double a, double b) const;
  const std::vector<std::pair<double, double>>& points() const { return points_; }

 private:
  std::vector<std::pair<double, double>> points_;
};

}  // namespace reach
