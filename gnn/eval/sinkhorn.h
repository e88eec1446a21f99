#pragma once
// The debiased Sinkhorn divergence between two clouds of equally weighted points (Feydy et al.
// 2019, "Interpolating between optimal transport and MMD"; LagrangeBench scores particle flows by
// it): the entropic optimal-transport cost of carrying one cloud onto the other, less half of each
// cloud's cost onto itself. It is 0 between a cloud and itself, grows with the squared distance the
// mass has to travel (a whole cloud shifted by d costs exactly |d|^2, whatever the epsilon), and,
// unlike per-particle error, does not care which particle went where: a forecast is scored on where
// the oil is, not on whether particle 512 is where particle 512 was.

#include <torch/torch.h>

namespace gnn {

struct SinkhornSettings {
  // Entropic regularisation, m^2 (the cost is the squared distance): transport over distances
  // below about sqrt(epsilon) is blurred. compare uses the particle diameter squared.
  double epsilon = 0;
  // Clouds larger than this are thinned by a fixed stride (cost O(n^2), result deterministic).
  int64_t max_points = 800;
  // Epsilon starts at the squared extent of the two clouds and shrinks by this factor per
  // iteration down to `epsilon` (annealing, for convergence within a few dozen iterations) ...
  double scaling = 0.5;
  // ... then iterations at `epsilon` go on until no potential moves by more than
  // tolerance * epsilon, at most max_iterations of them.
  double tolerance = 1e-6;
  int max_iterations = 200;
};

// S_eps(a, b) in m^2 for point clouds a [n, d], b [m, d] (any floating type; computed in double).
// 0 when both are empty; NaN when only one is (there is nothing to carry the mass to). Throws
// std::invalid_argument for epsilon <= 0 or clouds of different dimension.
double sinkhorn_divergence(const torch::Tensor& a, const torch::Tensor& b,
                           const SinkhornSettings& settings);

}  // namespace gnn
