#include "gnn/eval/fractions_skill.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace gnn {

namespace {

// The occupied cells of one footprint, as integer (column, row) pairs.
std::vector<std::pair<int64_t, int64_t>> occupied_cells(const torch::Tensor& xy, double cell) {
  const torch::Tensor c =
      torch::floor(xy.to(torch::kFloat64) / cell).to(torch::kInt64).contiguous();
  std::vector<std::pair<int64_t, int64_t>> out;
  if (c.numel() == 0) return out;
  auto a = c.accessor<int64_t, 2>();
  for (int64_t i = 0; i < c.size(0); ++i) out.emplace_back(a[i][0], a[i][1]);
  return out;
}

}  // namespace

double fractions_skill_score(const torch::Tensor& forecast_xy, const torch::Tensor& observed_xy,
                             double cell, int64_t window_cells) {
  if (!(cell > 0)) throw std::invalid_argument("fractions_skill_score: cell must be > 0");
  if (window_cells < 1)
    throw std::invalid_argument("fractions_skill_score: the window must be at least one cell");
  const auto forecast = occupied_cells(forecast_xy, cell);
  const auto observed = occupied_cells(observed_xy, cell);
  if (forecast.empty() && observed.empty()) return std::nan("");
  if (forecast.empty() || observed.empty()) return 0.0;

  // A grid holding both footprints, widened by a window on every side: every window position
  // that touches an occupied cell has its lower corner inside it.
  int64_t x0 = std::numeric_limits<int64_t>::max(), y0 = x0;
  int64_t x1 = std::numeric_limits<int64_t>::min(), y1 = x1;
  for (const auto* set : {&forecast, &observed})
    for (const auto& [x, y] : *set) {
      x0 = std::min(x0, x);
      x1 = std::max(x1, x);
      y0 = std::min(y0, y);
      y1 = std::max(y1, y);
    }
  const int64_t n = window_cells;
  x0 -= n;
  y0 -= n;
  const double width = double(x1 - x0 + 1), height = double(y1 - y0 + 1);
  if (width * height > 1e8)
    throw std::invalid_argument("fractions_skill_score: the footprints span more than 1e8 cells");
  const int64_t w = x1 - x0 + 1, h = y1 - y0 + 1;

  // Summed-area tables (one row and column of zeros first) of each binary field.
  const auto summed = [&](const std::vector<std::pair<int64_t, int64_t>>& cells) {
    std::vector<double> s(size_t((w + 1) * (h + 1)), 0.0);
    // Set, not added: several points in one cell occupy it once.
    for (const auto& [x, y] : cells) s[size_t((y - y0 + 1) * (w + 1) + (x - x0 + 1))] = 1.0;
    for (int64_t j = 1; j <= h; ++j)
      for (int64_t i = 1; i <= w; ++i)
        s[size_t(j * (w + 1) + i)] += s[size_t((j - 1) * (w + 1) + i)] +
                                      s[size_t(j * (w + 1) + i - 1)] -
                                      s[size_t((j - 1) * (w + 1) + i - 1)];
    return s;
  };
  const std::vector<double> sf = summed(forecast), so = summed(observed);
  // The occupied count of the window whose lower corner is cell (i, j) of the grid, cut to it.
  const auto window_sum = [&](const std::vector<double>& s, int64_t i, int64_t j) {
    const int64_t i1 = std::min(i + n, w), j1 = std::min(j + n, h);
    return s[size_t(j1 * (w + 1) + i1)] - s[size_t(j * (w + 1) + i1)] -
           s[size_t(j1 * (w + 1) + i)] + s[size_t(j * (w + 1) + i)];
  };
  const double area = double(n * n);
  double mismatch = 0, reference = 0;
  for (int64_t j = 0; j < h; ++j)
    for (int64_t i = 0; i < w; ++i) {
      const double f = window_sum(sf, i, j) / area, o = window_sum(so, i, j) / area;
      mismatch += (f - o) * (f - o);
      reference += f * f + o * o;
    }
  return 1.0 - mismatch / reference;
}

}  // namespace gnn
