#pragma once
// GNS (Sanchez-Gonzalez et al. 2020, "Learning to Simulate Complex Physics with Graph
// Networks"), as docs/models.md specifies: encode-process-decode with MLPs of `mlp_hidden_layers`
// hidden layers (ReLU) and LayerNorm on encoders and processor, `layers` interaction-network
// steps with separate weights and residuals on nodes and edges, sum aggregation to receivers,
// and a decoder without LayerNorm to 4 outputs: the acceleration and the oil fraction's change.
//
// CPU hot path: the edge MLP's first layer on [e_ij, v_i, v_j] (3 x latent wide) is split into
// W_e e_ij + (W_r V)[receiver] + (W_s V)[sender]: the node projections cost one [n, L] x [L, 2L]
// product and a gather instead of building and multiplying an [E, 3L] matrix (E is ~20 n).

#include <vector>

#include "common/param_spec.h"
#include "gnn/graph/segment_ops.h"
#include "gnn/models/graph_model.h"
#include "gnn/models/mlp.h"
#include "gnn/models/model_input_config.h"

namespace gnn {

struct GnsConfig {
  std::string model = "gns";
  int latent = 128;
  int layers = 10;
  int mlp_hidden_layers = 2;
  ModelInputConfig input;  // radius, noise_std, type_embedding

  template <class V>
  void describe(V& v) {
    using common::param;
    v.field("model", model, param("", "model name").one_of({"gns"}).require());
    v.field("latent", latent,
            param("", "width of every latent vector and hidden layer").at_least(1));
    v.field("layers", layers, param("", "message-passing steps of the processor").at_least(1));
    v.field("mlp_hidden_layers", mlp_hidden_layers,
            param("", "hidden layers of every MLP").at_least(1));
    input.describe(v);
  }
};

class GnsModel : public GraphModel {
 public:
  explicit GnsModel(const GnsConfig& config);
  // The registry's factory: validates `config` (errors name `file` and the key).
  static std::shared_ptr<GraphModel> from_config(const nlohmann::json& config,
                                                 const std::string& file);
  // The three stages, public so benchmarks can time the processor alone.
  struct Latents {
    torch::Tensor nodes, edges;
  };
  Latents encode(const GraphInput& graph);
  // With `node_latents` / `edge_latents`, each layer's latents are appended to them.
  Latents process(Latents latents, const GraphInput& graph,
                  std::vector<torch::Tensor>* node_latents = nullptr,
                  std::vector<torch::Tensor>* edge_latents = nullptr);
  torch::Tensor decode(const Latents& latents);
  // Multiply-add FLOPs (2 per multiply-add) of the processor's matrix products for a graph.
  double processor_flops(int64_t nodes, int64_t edges) const;
  double flops(int64_t nodes, int64_t edges) const override;
  std::string name() const override { return "gns"; }
  const ModelInputConfig& input_config() const override { return config_.input; }
  nlohmann::json config() const override;
  const GnsConfig& gns_config() const { return config_; }
  // Training on the CPU runs each processor step with its hand-written backward
  // (gns_processor_step.h); off, through LibTorch's autograd (the reference it is tested
  // against).
  void use_lean_backward(bool on) { lean_backward_ = on; }
  bool trains_in_chunks() const override { return lean_backward_; }
  bool infers_on_one_blas_thread() const override { return true; }

 protected:
  ModelOutput run(const GraphInput& graph, const ForwardOptions& options) override;

 private:
  // Inference helpers (no autograd, BLAS single-threaded by the caller): x W^T in row chunks
  // side by side; the node MLP of step k with its residual, in place on v.
  torch::Tensor rows_times_transposed(const torch::Tensor& x, const torch::Tensor& w);
  void node_update_in_chunks(size_t k, torch::Tensor& v, const torch::Tensor& aggregated);
  // The edge MLP of step k over chunks of edges, without autograd.
  torch::Tensor edge_update_in_chunks(size_t k, const torch::Tensor& e,
                                      const torch::Tensor& projected, const EdgeOrder& order);
  GnsConfig config_;
  bool lean_backward_ = true;
  torch::nn::Embedding type_embedding_{nullptr};
  Mlp node_encoder_{nullptr}, edge_encoder_{nullptr}, decoder_{nullptr};
  // Per processor step: the edge MLP (its first Linear applied to e_ij only) with the receiver
  // and sender projections of its first layer, and the node MLP likewise split into v_i and the
  // aggregated messages.
  std::vector<Mlp> edge_mlp_, node_mlp_;
  std::vector<torch::nn::Linear> receiver_sender_, aggregate_;
};

}  // namespace gnn
