#pragma once
// Top views (river map view: flow down the picture) of the ground truth and a learned
// simulator's rollout at the same frame, side by side: truth on the left, prediction on the
// right, as the README's comparison pictures show them.

#include <torch/torch.h>

#include <string>

#include "gnn/data/dataset.h"

namespace infer {

class SideBySideRenderer {
 public:
  SideBySideRenderer(const gnn::Trajectory& trajectory, const gnn::DatasetMetadata& metadata,
                     int width = 480);
  // positions [N, 3], active [N] bool of the truth and of the prediction at one frame.
  void write(const std::string& png, const torch::Tensor& truth, const torch::Tensor& truth_active,
             const torch::Tensor& predicted, const torch::Tensor& predicted_active) const;

 private:
  struct Impl;
  std::shared_ptr<Impl> impl_;
};

}  // namespace infer
