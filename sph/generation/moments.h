#pragma once
// The sums behind a dataset's normalisation statistics, kept per trajectory so that the
// statistics do not depend on how the trajectories were simulated (in one process, resumed, or
// in parts).

#include <algorithm>
#include <array>
#include <cmath>
#include <nlohmann/json.hpp>
#include <vector>

#include "sph/core/types.h"

namespace sph {

// Running first and second moments of 3-vectors, for the normalisation statistics.
struct Moments {
  double count = 0;
  std::array<double, 3> sum{}, sum_sq{};
  void add(const Vec3d& v) {
    count += 1;
    for (int k = 0; k < 3; ++k) sum[size_t(k)] += v[k], sum_sq[size_t(k)] += v[k] * v[k];
  }
  void add(const Moments& m) {
    count += m.count;
    for (size_t k = 0; k < 3; ++k) sum[k] += m.sum[k], sum_sq[k] += m.sum_sq[k];
  }
  nlohmann::json to_json() const { return {{"count", count}, {"sum", sum}, {"sum_sq", sum_sq}}; }
  static Moments from_json(const nlohmann::json& j) {
    Moments m;
    m.count = j.at("count");
    m.sum = j.at("sum");
    m.sum_sq = j.at("sum_sq");
    return m;
  }
  std::vector<double> mean() const {
    std::vector<double> out(3, 0);
    for (size_t k = 0; k < 3; ++k) out[k] = count > 0 ? sum[k] / count : 0;
    return out;
  }
  std::vector<double> std_dev() const {
    std::vector<double> out(3, 0), m = mean();
    for (size_t k = 0; k < 3; ++k)
      out[k] = count > 0 ? std::sqrt(std::max(0.0, sum_sq[k] / count - m[k] * m[k])) : 0;
    return out;
  }
};

}  // namespace sph
