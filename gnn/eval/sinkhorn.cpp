#include "gnn/eval/sinkhorn.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace gnn {

namespace {

torch::Tensor thinned(const torch::Tensor& x, int64_t max_points) {
  const torch::Tensor d = x.to(torch::kFloat64).contiguous();
  if (max_points <= 0 || d.size(0) <= max_points) return d;
  const int64_t stride = (d.size(0) + max_points - 1) / max_points;
  return d.slice(0, 0, d.size(0), stride).contiguous();
}

// The soft minimum over j of C_ij - h_j (h: a dual potential plus eps times the log weights):
// -eps log sum_j exp((h_j - C_ij) / eps), computed stably by logsumexp.
torch::Tensor softmin(double eps, const torch::Tensor& cost, const torch::Tensor& h) {
  return -eps * torch::logsumexp((h.unsqueeze(0) - cost) / eps, 1);
}

}  // namespace

double sinkhorn_divergence(const torch::Tensor& a_in, const torch::Tensor& b_in,
                           const SinkhornSettings& s) {
  if (!(s.epsilon > 0)) throw std::invalid_argument("sinkhorn_divergence: epsilon must be > 0");
  if (a_in.dim() != 2 || b_in.dim() != 2 || a_in.size(1) != b_in.size(1))
    throw std::invalid_argument("sinkhorn_divergence: clouds must be [n, d] of one dimension d");
  if (a_in.size(0) == 0 && b_in.size(0) == 0) return 0.0;
  if (a_in.size(0) == 0 || b_in.size(0) == 0) return std::nan("");
  torch::NoGradGuard no_grad;
  const torch::Tensor a = thinned(a_in, s.max_points), b = thinned(b_in, s.max_points);
  const auto cost = [](const torch::Tensor& x, const torch::Tensor& y) {
    return torch::cdist(x, y).pow(2);
  };
  const torch::Tensor c_ab = cost(a, b), c_ba = c_ab.t().contiguous();
  const torch::Tensor c_aa = cost(a, a), c_bb = cost(b, b);
  // Uniform weights: log(1/n) for every point.
  const double log_a = -std::log(double(a.size(0))), log_b = -std::log(double(b.size(0)));

  // Start where every point sees the others as one blur: epsilon at the clouds' squared extent.
  const torch::Tensor both = torch::cat({a, b});
  const double extent2 =
      (std::get<0>(both.max(0)) - std::get<0>(both.min(0))).pow(2).sum().item<double>();
  double eps = std::max(extent2, s.epsilon);
  // f_ba: a's potential towards b; g_ab: b's towards a; f_aa, g_bb: each onto itself.
  torch::Tensor f_ba = softmin(eps, c_ab, torch::full({b.size(0)}, eps * log_b, torch::kFloat64));
  torch::Tensor g_ab = softmin(eps, c_ba, torch::full({a.size(0)}, eps * log_a, torch::kFloat64));
  torch::Tensor f_aa = softmin(eps, c_aa, torch::full({a.size(0)}, eps * log_a, torch::kFloat64));
  torch::Tensor g_bb = softmin(eps, c_bb, torch::full({b.size(0)}, eps * log_b, torch::kFloat64));
  // Symmetric (averaged) updates: they converge where the alternating ones oscillate.
  const auto iterate = [&](double e) {
    const torch::Tensor f_ba_new = softmin(e, c_ab, g_ab + e * log_b);
    const torch::Tensor g_ab_new = softmin(e, c_ba, f_ba + e * log_a);
    const torch::Tensor f_aa_new = softmin(e, c_aa, f_aa + e * log_a);
    const torch::Tensor g_bb_new = softmin(e, c_bb, g_bb + e * log_b);
    // Each averaged potential moves by half the difference.
    const auto half_change = [](const torch::Tensor& old, const torch::Tensor& fresh) {
      return (fresh - old).abs().max().item<double>() / 2;
    };
    const double moved = std::max({half_change(f_ba, f_ba_new), half_change(g_ab, g_ab_new),
                                   half_change(f_aa, f_aa_new), half_change(g_bb, g_bb_new)});
    f_ba = 0.5 * (f_ba + f_ba_new);
    g_ab = 0.5 * (g_ab + g_ab_new);
    f_aa = 0.5 * (f_aa + f_aa_new);
    g_bb = 0.5 * (g_bb + g_bb_new);
    return moved;
  };
  while (eps > s.epsilon) {
    eps = std::max(s.epsilon, eps * s.scaling);
    iterate(eps);
  }
  for (int k = 0; k < s.max_iterations; ++k)
    if (iterate(s.epsilon) <= s.tolerance * s.epsilon) break;
  // One last full (not averaged) update of each potential from the others, as the dual's value
  // is taken at the potentials that answer each other.
  const torch::Tensor f_ba_end = softmin(s.epsilon, c_ab, g_ab + s.epsilon * log_b);
  const torch::Tensor g_ab_end = softmin(s.epsilon, c_ba, f_ba + s.epsilon * log_a);
  const torch::Tensor f_aa_end = softmin(s.epsilon, c_aa, f_aa + s.epsilon * log_a);
  const torch::Tensor g_bb_end = softmin(s.epsilon, c_bb, g_bb + s.epsilon * log_b);
  // OT_eps(a, b) = <alpha, f_ba> + <beta, g_ab>; OT_eps(a, a) = 2 <alpha, f_aa>.
  return ((f_ba_end - f_aa_end).mean() + (g_ab_end - g_bb_end).mean()).item<double>();
}

}  // namespace gnn
