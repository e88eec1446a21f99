#pragma once
// A graph model together with everything needed to use it on particles: the normalisation
// statistics, the domain bounds and the input pipeline of docs/models.md. It turns a window of
// positions and the particles' oil fractions into a graph (node and edge features), the model's
// normalised output into an acceleration and a change of the oil fraction, advances positions by
// semi-implicit Euler in frame units (v' = v + a, x' = x + v') and the oil fractions by a local
// update that keeps the oil volume (local_fraction_update).

#include <torch/torch.h>

#include <array>
#include <memory>
#include <string>

#include "gnn/data/normalisation.h"
#include "gnn/models/graph_model.h"

namespace gnn {

// The fluid particles of one frame and the static boundary around them.
struct FrameNodes {
  torch::Tensor history;       // [n, 6, 3] float32 positions, oldest first
  torch::Tensor oil_fraction;  // [n] float32 in [0, 1] at the newest position; the node type
                               // (oil when >= 1/2) and the material features follow from it
  torch::Tensor material;      // [3, 2] float32 material features by type
  torch::Tensor boundary;      // [M, 3] float32 boundary positions (those near fluid become nodes)
};

// The fluid particles' state one frame on.
struct NextState {
  torch::Tensor position;      // [n, 3] float32
  torch::Tensor oil_fraction;  // [n] float32
};

// The model's normalised outputs for the fluid nodes.
struct NormalisedPrediction {
  torch::Tensor acceleration;         // [n, 3]
  torch::Tensor oil_fraction_change;  // [n]
};

// New oil fractions [n] from the old ones [n] and a predicted change [n], moving oil only along
// `pairs` [2, E] int64 (fluid particles within the graph radius of each other, both directions
// of a pair listed, as the radius graph lists them; self pairs ignored). As MTDF-SPH's mixture
// model does, oil flows between neighbours: a particle asking to gain takes from its neighbours
// that offer to lose, each pair's flux the product of the gain asked and the loss offered over
// the larger of what the receiver's neighbours offer and the sender's neighbours ask, so no
// particle gains more than it asked (nor beyond 1) or loses more than it offered (nor below 0).
// The sum (the oil volume, every particle having the same rest volume) is what it was to double
// precision, and a particle with no oil within its radius gains none: no traces far from the
// slick (a global correction spread them over the whole river).
torch::Tensor local_fraction_update(const torch::Tensor& fraction, const torch::Tensor& change,
                                    const torch::Tensor& pairs);

// Throws std::invalid_argument naming `where`, the tensor and its sizes when `nodes` does not
// have the shapes and dtypes above (CPU tensors).
void check_frame_nodes(const FrameNodes& nodes, const std::string& where);

using Bounds = std::array<std::array<double, 2>, 3>;

class LearnedSimulator {
 public:
  // `particle_radius` (m, of the data) is needed only by a model that reads the heterogeneous
  // typing, whose kernel sums weigh neighbours by the particles' volume.
  LearnedSimulator(std::shared_ptr<GraphModel> model, Normalisation normalisation, Bounds bounds,
                   double particle_radius = 0);

  GraphModel& model() { return *model_; }
  std::shared_ptr<GraphModel> model_ptr() { return model_; }
  const Normalisation& normalisation() const { return normalisation_; }
  const Bounds& bounds() const { return bounds_; }
  double particle_radius() const { return particle_radius_; }

  // Moves the model to `device` (default: the CPU). The input pipeline (radius graph, features)
  // runs on the CPU and its graph is handed to the model's device; predictions come back to the
  // CPU, so callers never see the device.
  void to(const torch::Device& device);
  torch::Device device() const { return model_->device(); }

  // Graph and features of a frame on the model's device; fluid nodes come first, in the order
  // of `nodes`. Checks the shapes and dtypes of `nodes`.
  GraphInput encode(const FrameNodes& nodes) const;
  // Normalised outputs for the fluid nodes (with autograd when enabled).
  NormalisedPrediction predict(const FrameNodes& nodes) {
    return predict(encode(nodes), nodes.history.size(0));
  }
  // The same on a frame's encoded graph whose first `fluid_count` nodes are the fluid.
  NormalisedPrediction predict(const GraphInput& graph, int64_t fluid_count);
  // Normalised acceleration of the fluid nodes [n, 3] alone.
  torch::Tensor predict_normalised(const FrameNodes& nodes) { return predict(nodes).acceleration; }
  torch::Tensor normalise_acceleration(const torch::Tensor& acceleration) const;
  torch::Tensor denormalise_acceleration(const torch::Tensor& normalised) const;
  torch::Tensor normalise_fraction_change(const torch::Tensor& change) const;
  torch::Tensor denormalise_fraction_change(const torch::Tensor& normalised) const;
  // Next positions and oil fractions of the fluid nodes (no autograd).
  NextState next_state(const FrameNodes& nodes);
  torch::Tensor next_position(const FrameNodes& nodes) { return next_state(nodes).position; }

 private:
  std::shared_ptr<GraphModel> model_;
  Normalisation normalisation_;
  Bounds bounds_;
  double particle_radius_ = 0;
};

}  // namespace gnn
