#include "gnn/eval/metrics.h"

#include <cmath>
#include <set>
#include <utility>

namespace gnn {

double position_mse(const torch::Tensor& predicted, const torch::Tensor& truth,
                    const torch::Tensor& mask) {
  auto error = (predicted - truth).pow(2).index({mask});
  return error.numel() ? error.mean().item<double>() : 0.0;
}

namespace {
torch::Tensor thin(const torch::Tensor& x, int64_t max_points) {
  if (x.size(0) <= max_points) return x;
  const int64_t stride = (x.size(0) + max_points - 1) / max_points;
  return x.slice(0, 0, x.size(0), stride);
}
}  // namespace

double mmd_rbf(const torch::Tensor& a_in, const torch::Tensor& b_in, double bandwidth,
               int64_t max_points) {
  auto a = thin(a_in, max_points).to(torch::kFloat64);
  auto b = thin(b_in, max_points).to(torch::kFloat64);
  if (a.size(0) == 0 || b.size(0) == 0) return 0.0;
  auto kernel = [&](const torch::Tensor& x, const torch::Tensor& y) {
    return torch::exp(-torch::cdist(x, y).pow(2) / (2 * bandwidth * bandwidth)).mean();
  };
  return (kernel(a, a) + kernel(b, b) - 2 * kernel(a, b)).item<double>();
}

double mean_kinetic_energy(const torch::Tensor& velocity, const torch::Tensor& mask) {
  auto v = velocity.index({mask});
  return v.size(0) ? 0.5 * v.pow(2).sum(1).mean().item<double>() : 0.0;
}

double top_view_iou(const torch::Tensor& a_xy, const torch::Tensor& b_xy, double cell) {
  auto cells = [&](const torch::Tensor& xy) {
    std::set<std::pair<int64_t, int64_t>> out;
    auto c = torch::floor(xy.to(torch::kFloat64) / cell).to(torch::kInt64).contiguous();
    auto a = c.accessor<int64_t, 2>();
    for (int64_t i = 0; i < c.size(0); ++i) out.insert({a[i][0], a[i][1]});
    return out;
  };
  const auto A = cells(a_xy), B = cells(b_xy);
  if (A.empty() && B.empty()) return 1.0;
  size_t common = 0;
  for (const auto& c : A) common += B.count(c);
  return double(common) / double(A.size() + B.size() - common);
}

}  // namespace gnn
