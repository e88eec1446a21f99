#pragma once
// A graph model together with everything needed to use it on particles: the normalisation
// statistics, the domain bounds and the input pipeline of MODELS.md. It turns a window of
// positions into a graph (node and edge features), the model's normalised output into an
// acceleration, and advances positions by semi-implicit Euler in frame units
// (v' = v + a, x' = x + v').

#include <torch/torch.h>

#include <array>
#include <memory>
#include <string>

#include "gnn/data/normalisation.h"
#include "gnn/models/graph_model.h"

namespace gnn {

// The fluid particles of one frame and the static boundary around them.
struct FrameNodes {
  torch::Tensor history;   // [n, 6, 3] float32 positions, oldest first
  torch::Tensor type;      // [n] int64, water or oil
  torch::Tensor material;  // [3, 2] float32 material features by type
  torch::Tensor boundary;  // [M, 3] float32 boundary positions (those near fluid become nodes)
};

// Throws std::invalid_argument naming `where`, the tensor and its sizes when `nodes` does not
// have the shapes and dtypes above (CPU tensors).
void check_frame_nodes(const FrameNodes& nodes, const std::string& where);

using Bounds = std::array<std::array<double, 2>, 3>;

class LearnedSimulator {
 public:
  LearnedSimulator(std::shared_ptr<GraphModel> model, Normalisation normalisation, Bounds bounds);

  GraphModel& model() { return *model_; }
  std::shared_ptr<GraphModel> model_ptr() { return model_; }
  const Normalisation& normalisation() const { return normalisation_; }
  const Bounds& bounds() const { return bounds_; }

  // Moves the model to `device` (default: the CPU). The input pipeline (radius graph, features)
  // runs on the CPU and its graph is handed to the model's device; predictions come back to the
  // CPU, so callers never see the device.
  void to(const torch::Device& device);
  torch::Device device() const { return model_->device(); }

  // Graph and features of a frame on the model's device; fluid nodes come first, in the order
  // of `nodes`. Checks the shapes and dtypes of `nodes`.
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
