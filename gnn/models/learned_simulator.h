#pragma once
// A graph model together with everything needed to use it on particles: the normalisation
// statistics, the domain bounds and the input pipeline of MODELS.md. It turns a window of
// positions into a graph (node and edge features), the model's normalised output into an
// acceleration, and advances positions by semi-implicit Euler in frame units
// (v' = v + a, x' = x + v').

#include <torch/torch.h>

#include <array>
#include <memory>

#include "gnn/data/normalisation.h"
#include "gnn/models/graph_model.h"

namespace gnn {

// The fluid particles of one frame and the static boundary around them.
struct FrameNodes {
  torch::Tensor history;   // [n, 6, 3] positions, oldest first
  torch::Tensor type;      // [n] int64, water or oil
  torch::Tensor material;  // [3, 2] material features by type
  torch::Tensor boundary;  // [M, 3] boundary positions (those near fluid become nodes)
};

using Bounds = std::array<std::array<double, 2>, 3>;

class LearnedSimulator {
 public:
  LearnedSimulator(std::shared_ptr<GraphModel> model, Normalisation normalisation, Bounds bounds);

  GraphModel& model() { return *model_; }
  std::shared_ptr<GraphModel> model_ptr() { return model_; }
  const Normalisation& normalisation() const { return normalisation_; }
  const Bounds& bounds() const { return bounds_; }

  // Graph and features of a frame; fluid nodes come first, in the order of `nodes`.
  GraphInput encode(const FrameNodes& nodes) const;
  // Normalised acceleration of the fluid nodes [n, 3] (with autograd when enabled).
  torch::Tensor predict_normalised(const FrameNodes& nodes);
  torch::Tensor normalise_acceleration(const torch::Tensor& acceleration) const;
  torch::Tensor denormalise_acceleration(const torch::Tensor& normalised) const;
  // Next positions [n, 3] of the fluid nodes (no autograd).
  torch::Tensor next_position(const FrameNodes& nodes);

 private:
  std::shared_ptr<GraphModel> model_;
  Normalisation normalisation_;
  Bounds bounds_;
};

}  // namespace gnn
