#pragma once
// Error measures of a rollout against the recording it replays.

#include <torch/torch.h>

namespace gnn {

// Mean over the selected particles and the 3 dimensions of the squared position error, m^2.
double position_mse(const torch::Tensor& predicted, const torch::Tensor& truth,
                    const torch::Tensor& mask);

// Maximum mean discrepancy (squared, biased estimate) between two point clouds with a Gaussian
// kernel of the given bandwidth (m). Clouds larger than `max_points` are thinned by a fixed
// stride, so the cost stays bounded and the result deterministic.
double mmd_rbf(const torch::Tensor& a, const torch::Tensor& b, double bandwidth,
               int64_t max_points = 1500);

// Mean kinetic energy per unit mass, 0.5 |v|^2 in (m/s)^2, of the selected particles.
double mean_kinetic_energy(const torch::Tensor& velocity, const torch::Tensor& mask);

// Intersection over union of two top-view masks: the grid cells (of side `cell`, m) holding at
// least one point of each set of xy positions. 1 when both are empty.
double top_view_iou(const torch::Tensor& a_xy, const torch::Tensor& b_xy, double cell);

}  // namespace gnn
