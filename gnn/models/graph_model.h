#pragma once
// The contract every learned simulator implements (GNS, DPI-Nets, PAGATNet and the
// constant-velocity floor): one graph in, a ModelOutput out. The registry (model_registry.cpp)
// builds a model from its JSON config by the config's "model" name, validating every key.
//
// forward() checks the graph (shapes, dtypes, contiguity, device) before the model sees it and
// runs on the model's device; models are used in train() mode for training and in eval() mode
// for validation and rollouts (batch normalisation behaves differently in the two).

#include <torch/torch.h>

#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "gnn/data/dataset.h"
#include "gnn/data/normalisation.h"
#include "gnn/graph/graph_input.h"
#include "gnn/graph/heterogeneous_typing.h"
#include "gnn/models/model_input_config.h"

namespace gnn {

// What the caller wants besides the acceleration.
struct ForwardOptions {
  // Keep the node and edge latents after every processor layer (distillation pairs a student's
  // layers with a teacher's); off, they are not kept and cost nothing.
  bool keep_latents = false;
  // Called after each processor layer with its node and edge latents (after they were kept),
  // which it may change in place: distillation's generator adds the teacher's adapted latents
  // to the student's during training (gnn/training/pagat_objective.h). Models without layers
  // of latents ignore it.
  std::function<void(size_t layer, torch::Tensor& nodes, torch::Tensor& edges)> after_layer;
};

// A model's output for one graph. Every model's head has kModelOutputs columns: the normalised
// acceleration and the normalised change of the oil fraction.
constexpr int64_t kModelOutputs = 4;

struct ModelOutput {
  torch::Tensor acceleration;  // [n, 3] normalised (only fluid rows are used)
  // [n] normalised change of the oil fraction over the frame (only fluid rows are used); the
  // simulator turns it into a local, conserving update (local_fraction_update).
  torch::Tensor oil_fraction_change;
  std::vector<torch::Tensor> node_latents;  // per processor layer [n, L]; empty unless asked
  std::vector<torch::Tensor> edge_latents;  // per processor layer [E, L]; empty unless asked
  // Outputs of auxiliary heads by name, e.g. PAGATNet's "node_class_logits" [n, 4].
  std::map<std::string, torch::Tensor> auxiliary;
};

class GraphModel : public torch::nn::Module {
 public:
  // Checks the graph, then runs the model.
  ModelOutput forward(const GraphInput& graph, const ForwardOptions& options) {
    check_graph_input(graph, name() + " forward");
    return run(graph, options);
  }
  // The normalised acceleration [n, 3] alone.
  torch::Tensor acceleration(const GraphInput& graph) {
    return forward(graph, ForwardOptions{}).acceleration;
  }

  virtual std::string name() const = 0;
  // The input settings every model's config shares (model_input_config.h).
  virtual const ModelInputConfig& input_config() const = 0;
  double radius() const { return input_config().radius; }        // connectivity radius, m
  double noise_std() const { return input_config().noise_std; }  // velocity noise, m per frame
  // Whether the model reads GraphInput::node_class and link_type (they are built only then).
  virtual bool needs_typing() const { return false; }
  // The surface rule of that typing (gnn/graph/heterogeneous_typing.h).
  virtual SurfaceRule surface_rule() const { return {}; }
  // Whether training runs the model's heavy products in row chunks side by side (then it wants
  // BLAS on one thread, see training_runtime in gnn/runtime/runtime.h).
  virtual bool trains_in_chunks() const { return false; }
  // Whether inference without autograd is fastest with BLAS on one thread and LibTorch on every
  // core (row chunks side by side, or products small enough that LibTorch's own threads do
  // better than BLAS's; measured per model, see inference_runtime).
  virtual bool infers_on_one_blas_thread() const { return false; }
  // The resolved config (defaults filled in), stored in checkpoints.
  virtual nlohmann::json config() const = 0;
  // The statistics the graph's velocities were normalised with and the output acceleration is
  // normalised with; LearnedSimulator passes its own when it takes the model (so also after a
  // checkpoint is loaded). A model whose head is not a normalised acceleration (DPI-Nets
  // predicts the next velocity, the constant-velocity floor zero acceleration) converts its
  // output with them; the default ignores them.
  virtual void set_normalisation(const Normalisation& /*normalisation*/) {}
  // Multiply-add FLOPs (2 per multiply-add) of one forward pass's matrix products on a graph of
  // `nodes` nodes and `edges` edges (gathers, sums and activations left out); < 0 when the model
  // does not say.
  virtual double flops(int64_t /*nodes*/, int64_t /*edges*/) const { return -1; }

  // The device of the model's parameters (where its inputs must be).
  torch::Device device() const {
    const auto p = parameters();
    return p.empty() ? torch::Device(torch::kCPU) : p.front().device();
  }

 protected:
  virtual ModelOutput run(const GraphInput& graph, const ForwardOptions& options) = 0;
};

// Builds the model named by config["model"]; `file` names the config in errors (ConfigError
// with the key path for unknown keys, wrong types and out-of-range values).
std::shared_ptr<GraphModel> make_model(const nlohmann::json& config, const std::string& file);

// The registered model names.
std::vector<std::string> model_names();

}  // namespace gnn
