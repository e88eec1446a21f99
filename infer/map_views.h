#pragma once
// Top views (river map view: flow down the picture) of recorded or predicted frames, and a grid
// to lay them out in: truth beside prediction for a rollout, a row per model for a comparison.
// A particle is drawn as oil when its oil fraction at that frame is at least 1/2.

#include <torch/torch.h>

#include <memory>
#include <string>
#include <vector>

#include "common/image_writer.h"
#include "gnn/data/dataset.h"
#include "gnn/eval/rollout.h"

namespace infer {

class MapViewRenderer {
 public:
  MapViewRenderer(const gnn::Trajectory& trajectory, const gnn::DatasetMetadata& metadata,
                  int width = 480);
  // positions [N, 3], active [N] bool and oil fractions [N] of one frame.
  common::RgbImage render(const torch::Tensor& position, const torch::Tensor& active,
                          const torch::Tensor& oil_fraction) const;
  // The probability of oiling at frame `frame` of an ensemble: each top-view cell of side `cell`
  // (m) that holds oil in any member drawn on top, shaded by the share of members with oil there
  // (the oil colour's scale: pale blue for few, near-black for all), over the first member's
  // water. How operational spill models show uncertainty.
  common::RgbImage render_oiling(const std::vector<gnn::RolloutResult>& members, int64_t frame,
                                 double cell) const;

 private:
  std::shared_ptr<common::FrameRenderer> renderer_;
  float top_ = 0;  // the domain's top (m): oiled cells are drawn there, above the water
};

// `rows` of images on a white page, `gap` pixels apart; each cell as large as the largest image.
common::RgbImage image_grid(const std::vector<std::vector<common::RgbImage>>& rows, int gap = 8);

}  // namespace infer
