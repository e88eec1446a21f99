#pragma once
// The Fractions Skill Score of a forecast footprint against the observed one (Roberts & Lean
// 2008, "Scale-selective verification of rainfall accumulations"): both footprints are binary
// top-view grids; each is turned into the fraction of occupied cells within an n x n window
// around every cell, and FSS = 1 - sum (F - O)^2 / (sum F^2 + sum O^2). A footprint displaced by
// less than the window still scores partly (1 - s/n for one cell moved s < n cells), so a slick
// forecast a little off is not scored as a miss twice, the way per-particle error and IoU score
// it. 1 is perfect, 0 is no skill at that scale.

#include <torch/torch.h>

namespace gnn {

// FSS of the footprints of two sets of top-view positions [n, 2] (m) on a grid of square cells of
// side `cell` (m), each cell occupied when it holds a point, over windows of `window_cells` x
// `window_cells` cells (the fractions are taken over every window position that touches an
// occupied cell, so no edge of the map cuts a footprint). 0 when exactly one footprint is empty;
// NaN when both are (nothing to score). Throws std::invalid_argument for cell <= 0,
// window_cells < 1, or footprints more than 10^8 cells apart.
double fractions_skill_score(const torch::Tensor& forecast_xy, const torch::Tensor& observed_xy,
                             double cell, int64_t window_cells);

}  // namespace gnn
