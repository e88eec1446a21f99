#pragma once
// DPI-Nets (Li, Wu, Tedrake, Tenenbaum and Torralba 2019, "Learning Particle Dynamics for
// Manipulating Rigid Bodies, Deformable Objects, and Fluids", ICLR), as docs/models.md specifies,
// without the hierarchy of rigid clusters (our scenes are fluid only):
//
//   particle encoding   c_i  = ReLU(MLP_O(s_i))                        [n, particle_width]
//   relation encoding   c_ij = ReLU(MLP_R(s_j, s_i, s_j - s_i, d_ij))  [E, relation_width]
//   L propagation steps, from h^0 = 0 (the paper's multi-step propagation; the two propagators
//   are shared by the steps, as in the paper):
//     relation effect   e_ij^l = ReLU(W_R [c_ij, h_i^(l-1), h_j^(l-1)] + b_R)     [E, effect]
//     particle effect   h_i^l  = h_i^(l-1) + ReLU(W_O [c_i, sum_j e_ij^l, h_i^(l-1)] + b_O)
//   decoder             u_i, r_i = MLP_D(h_i^L)                                    [n, 3 + 1]
//
// where s_i is a node's state (its normalised features of graph_input.h and the learned
// embedding of its type), d_ij the edge features ((x_j - x_i) / radius and its norm) and edge
// (j -> i) runs from sender j to receiver i; effects are summed to receivers with the CSR ops of
// segment_ops.h. The relation encoder's first layer acts on [s_j, s_i, s_j - s_i]: a linear map
// of that is W_a s_j + W_b s_i + W_c (s_j - s_i) = (W_a + W_c) s_j + (W_b - W_c) s_i, so it is
// computed as two per-node projections gathered to the edges (one [n, 39] x [39, 2R] product
// instead of an [E, 121] x [121, R] one; the same set of functions, E is ~20 n). Likewise the
// propagators' parts on c_ij, c_i and their biases are the same in every step and are computed
// once.
//
// The output. The decoder predicts the next velocity u = (v_(t+1) - vel_mean) / vel_std, in the
// normalisation of the input velocities (the paper's model predicts velocities). The shared
// interface wants the acceleration that semi-implicit Euler applies (LearnedSimulator:
// v_(t+1) = v_t + a, x_(t+1) = x_t + v_(t+1), frame units), normalised as the training target is
// (a - acc_mean) / acc_std. The node features carry the newest velocity in the same velocity
// normalisation, f = (v_t - vel_mean) / vel_std (columns kLastVelocityColumn.., noise included in
// training, which is what the noise-corrected target expects), so
//   a = v_(t+1) - v_t = (u - f) vel_std            (the velocity mean cancels)
//   acceleration = ((u - f) vel_std - acc_mean) / acc_std,
// per component, with the statistics LearnedSimulator hands over (set_normalisation). Note the
// factor vel_std / acc_std (~10 on the tiny test dataset, more on slow-changing flows): an error
// in u counts that many times over in the normalised-acceleration loss; it is the price of the
// paper's velocity head. The decoder's fourth column r_i is the normalised change of the oil
// fraction, the output every model shares (graph_model.h).

#include <vector>

#include "common/param_spec.h"
#include "gnn/graph/segment_ops.h"
#include "gnn/models/graph_model.h"
#include "gnn/models/mlp.h"
#include "gnn/models/model_input_config.h"

namespace gnn {

struct DpiConfig {
  std::string model = "dpi";
  int particle_width = 200;
  int relation_width = 300;
  int effect_width = 200;
  int propagation_steps = 3;
  int encoder_hidden_layers = 2;
  ModelInputConfig input;  // radius, noise_std, type_embedding

  template <class V>
  void describe(V& v) {
    using common::param;
    v.field("model", model, param("", "model name").one_of({"dpi"}).require());
    v.field("particle_width", particle_width,
            param("", "width of the particle encoder (hidden layers and output)").at_least(1));
    v.field("relation_width", relation_width,
            param("", "width of the relation encoder (hidden layers and output)").at_least(1));
    v.field("effect_width", effect_width,
            param("", "width of the particle and relation effects of the propagation").at_least(1));
    v.field("propagation_steps", propagation_steps,
            param("", "propagation steps L (shared weights)").at_least(1).at_most(20));
    v.field("encoder_hidden_layers", encoder_hidden_layers,
            param("", "hidden layers of the particle and relation encoders").at_least(1));
    input.describe(v);
  }
};

class DpiModel : public GraphModel {
 public:
  explicit DpiModel(const DpiConfig& config);
  // The registry's factory: validates `config` (errors name `file` and the key).
  static std::shared_ptr<GraphModel> from_config(const nlohmann::json& config,
                                                 const std::string& file);
  std::string name() const override { return "dpi"; }
  const ModelInputConfig& input_config() const override { return config_.input; }
  nlohmann::json config() const override;
  void set_normalisation(const Normalisation& normalisation) override;
  double flops(int64_t nodes, int64_t edges) const override;
  // Inference runs in row chunks side by side (dpi_inference.cpp), as GNS's does, BLAS on one.
  bool infers_on_one_blas_thread() const override { return true; }

  // The decoder's output alone, the normalised next velocity u [n, 3], for a checked graph
  // (needs no normalisation statistics).
  torch::Tensor next_velocity(const GraphInput& graph);

 protected:
  // Throws std::logic_error when no normalisation was set (the output needs it).
  ModelOutput run(const GraphInput& graph, const ForwardOptions& options) override;

 private:
  // u [n, 3], with the per-step effects appended to `node_latents` / `edge_latents` when given.
  torch::Tensor propagate(const GraphInput& graph, std::vector<torch::Tensor>* node_latents,
                          std::vector<torch::Tensor>* edge_latents);
  // The same function without autograd in fewer passes over the edges (dpi_inference.cpp), for
  // float32 CPU graphs whose edge order is canonical and when no latents are asked for.
  bool can_propagate_in_chunks(const GraphInput& graph, const EdgeOrder& order) const;
  torch::Tensor propagate_in_chunks(const GraphInput& graph, const EdgeOrder& order);
  DpiConfig config_;
  torch::nn::Embedding type_embedding_{nullptr};
  Mlp particle_encoder_{nullptr};
  // The relation encoder: its first Linear applied to the edge features; the node states'
  // parts of that layer are `relation_nodes_` ([sender | receiver] projections, no bias).
  Mlp relation_encoder_{nullptr};
  torch::nn::Linear relation_nodes_{nullptr};
  // Relation propagator: `relation_code_` on c_ij (with the bias), `relation_effects_` on
  // [h_receiver | h_sender] as one [n, 2 effect] projection (no bias).
  torch::nn::Linear relation_code_{nullptr}, relation_effects_{nullptr};
  // Particle propagator: `particle_code_` on c_i (with the bias), `particle_sum_` on the summed
  // relation effects and `particle_self_` on h_i (no biases).
  torch::nn::Linear particle_code_{nullptr}, particle_sum_{nullptr}, particle_self_{nullptr};
  Mlp decoder_{nullptr};
  // From set_normalisation: acceleration = (u - f) * velocity_scale_ + acceleration_offset_.
  torch::Tensor velocity_scale_;       // [3] vel_std / acc_std
  torch::Tensor acceleration_offset_;  // [3] -acc_mean / acc_std
};

}  // namespace gnn
