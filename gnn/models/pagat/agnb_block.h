#pragma once
// One processor step of PAGATNet (docs/models.md, "AGNB block") and the plain GN block that
// replaces it with "processor": "gn". Both map node latents v [n, L] and edge latents e [E, L] to
// new ones, with residuals.
//
// AGNB, our reading of the paper's equations:
//  1. Position-aware module ("Conv" = a 1x1 convolution = Linear; BN = batch normalisation over
//     the node or edge axis):
//       e'  = BN(Linear(MLP([e_ab, v_a, v_b])))                       a: receiver, b: sender
//       v'  = BN(Linear(MLP(v_a))) + sum_b MLP(e'_ab)
//       u'  = BN(Linear(MLP(v_a))) + MLP(v_a)                          (the velocity channel)
//     The node state the rest of the block reads is h = v' + u': docs/models.md names the velocity
//     channel but not where it goes; adding it to the position channel keeps one node width.
//  2. Attention per link type T (ST, SP, DP, BD), GATv2 form with `heads` heads of L / heads
//     channels: s_ab,k = a_T,k . LeakyReLU(W_T,src h_b + W_T,dst h_a + W_T,e e'_ab)_k, plus the
//     physics-aware module's bias for head k; a softmax over a's neighbours of type T
//     (segment_softmax); the heads' weights are averaged (the paper's eq. 57). Without content
//     attention (the ablation) s_ab,k is the physics bias alone, or 0 (equal weights) without it.
//  3. Messages phi_A = LN(ReLU(MLP([e'_ab, h_a, h_b]))) on every edge, aggregated per type with
//     the attention weights alpha:
//       STA = phi_B([h_a, sum alpha phi_A * phi_A])    (the attention-gated product)
//       SPA = phi_B([sum alpha phi_A, h_a])
//       DPA = x + MLP(LN(MLP(x))),  x = phi_B([h_a, sum alpha phi_A])   (the paper's eq. 46)
//       BD  = phi_B([sum alpha phi_A, h_a])
//     each phi_B = LN(ReLU(MLP(.))) with its own weights. A node with no edges of a type gets a
//     zero sum for it.
//  4. v <- v + MLP([h, STA, SPA, DPA, BD]) (LayerNorm at its end, as GNS's node MLP); e <- e + e'.
//
// CPU cost: as in GNS, a first layer on [e_ab, v_a, v_b] is computed as W_e e_ab + (W_a v)[a] +
// (W_b v)[b] (per-node projections gathered to the edges, not an [E, 3L] product: E is ~8 n),
// and so are the attention's W_T,src h_b and W_T,dst h_a; only W_T,e e'_ab is per edge.
// Inference (no autograd, eval mode, float32 on the CPU, edges sorted by receiver) takes a fused
// path, pagat/agnb_inference.cpp: the same function in row chunks and one pass per receiver.
//
// GN block ("processor": "gn", plain GN blocks instead of AGNB): GNS's interaction step,
//   e <- e + MLP([e_ab, v_a, v_b]),  v <- v + MLP([v_a, sum_b e_ab]),  LayerNorm on both MLPs.

#include <torch/torch.h>

#include <array>

#include "gnn/graph/heterogeneous_typing.h"
#include "gnn/graph/segment_ops.h"
#include "gnn/models/mlp.h"

namespace gnn {

// What every block reads of the typed graph, computed once per forward pass.
struct TypedGraph {
  EdgeOrder order;                                  // the whole edge list
  std::array<TypedEdges, kLinkTypes> types;         // its edges by link type, CSR by receiver
  std::array<torch::Tensor, kLinkTypes> receivers;  // each type's edges' receivers [E_T]
  std::array<torch::Tensor, kLinkTypes> senders;    // and senders [E_T]
  torch::Tensor link_type;                          // [E] int64, contiguous: every edge's link type
  torch::Tensor physics_bias;  // [E, heads] attention biases, undefined when the module is off
  int64_t nodes = 0;
};

TypedGraph typed_graph(const torch::Tensor& edge_index, const torch::Tensor& link_type,
                       int64_t nodes);

struct BlockLatents {
  torch::Tensor nodes, edges;  // [n, L], [E, L]
};

class ProcessorBlock : public torch::nn::Module {
 public:
  virtual BlockLatents forward(const BlockLatents& in, const TypedGraph& graph) = 0;
  // Multiply-add FLOPs of the block's matrix products on a graph.
  virtual double flops(int64_t nodes, int64_t edges) const = 0;
};

// LN(ReLU(MLP(x))): phi_A and phi_B of the paper.
class NormalisedMlpImpl : public torch::nn::Module {
 public:
  NormalisedMlpImpl(int64_t in, int64_t width, int hidden_layers);
  torch::Tensor forward(const torch::Tensor& x);
  // The rest after the first Linear was applied (its pre-activation output).
  torch::Tensor forward_after_first(const torch::Tensor& first_pre_activation);
  torch::nn::Linear first() { return mlp_->first(); }
  Mlp mlp() { return mlp_; }
  torch::nn::LayerNorm norm() { return norm_; }
  double flops_per_row() const { return mlp_->flops_per_row(); }

 private:
  Mlp mlp_{nullptr};
  torch::nn::LayerNorm norm_{nullptr};
};
TORCH_MODULE(NormalisedMlp);

class AgnbBlock : public ProcessorBlock {
 public:
  // content_attention false: no learned scores (W_src, W_dst, W_e, a), the ablation.
  AgnbBlock(int64_t latent, int64_t heads, int hidden_layers, bool content_attention = true);
  BlockLatents forward(const BlockLatents& in, const TypedGraph& graph) override;
  double flops(int64_t nodes, int64_t edges) const override;
  // Whether forward takes the fused inference path (agnb_inference.cpp) on these inputs: no
  // autograd, eval mode, float32 on the CPU, edges sorted by receiver and symmetric.
  bool can_run_in_chunks(const BlockLatents& in, const TypedGraph& graph) const;

 private:
  BlockLatents forward_in_chunks(const BlockLatents& in, const TypedGraph& graph);
  // Its passes (agnb_inference.cpp): over the edges, the nodes, the edges again, then the nodes.
  struct EdgePass;
  struct NodePass;
  EdgePass edge_pass(const torch::Tensor& v, const torch::Tensor& e, const TypedGraph& graph);
  NodePass node_pass(const torch::Tensor& v, const torch::Tensor& summed);
  std::pair<torch::Tensor, torch::Tensor> message_pass(const EdgePass& edges, const NodePass& nodes,
                                                       const TypedGraph& graph);
  torch::Tensor node_update_pass(const torch::Tensor& v, const torch::Tensor& h,
                                 const torch::Tensor& aggregated);
  // BN over the rows; a batch of one row or none in training uses the running statistics
  // (batch statistics of a single row are undefined).
  torch::Tensor batch_norm(torch::nn::BatchNorm1d& bn, const torch::Tensor& x);
  // The attention scores [E_T, heads] of link type t's edges.
  torch::Tensor scores(size_t t, const torch::Tensor& h, const torch::Tensor& e1,
                       const TypedGraph& g);
  int64_t latent_, heads_;
  bool content_attention_;
  // Position-aware module; the edge MLP's first layer acts on e, `edge_nodes_` holds its parts
  // on the receiver's and the sender's latents ([receiver | sender], no bias).
  Mlp edge_mlp_{nullptr}, edge_message_{nullptr}, node_mlp_{nullptr}, velocity_mlp_{nullptr},
      velocity_skip_{nullptr};
  torch::nn::Linear edge_nodes_{nullptr};
  torch::nn::Linear edge_conv_{nullptr}, node_conv_{nullptr}, velocity_conv_{nullptr};
  torch::nn::BatchNorm1d edge_bn_{nullptr}, node_bn_{nullptr}, velocity_bn_{nullptr};
  // Attention per link type: W_src, W_dst (per node), W_e (no biases but W_dst's) and a
  // [heads, L / heads].
  std::array<torch::nn::Linear, kLinkTypes> source_{nullptr, nullptr, nullptr, nullptr},
      target_{nullptr, nullptr, nullptr, nullptr}, edge_{nullptr, nullptr, nullptr, nullptr};
  std::array<torch::Tensor, kLinkTypes> attention_;
  // Messages; phi_A's first layer acts on e', `phi_a_nodes_` on [h_receiver | h_sender].
  NormalisedMlp phi_a_{nullptr};
  torch::nn::Linear phi_a_nodes_{nullptr};
  std::array<NormalisedMlp, kLinkTypes> phi_b_{nullptr, nullptr, nullptr, nullptr};
  Mlp dp_inner_{nullptr}, dp_outer_{nullptr};
  torch::nn::LayerNorm dp_norm_{nullptr};
  Mlp update_{nullptr};
};

class GnBlock : public ProcessorBlock {
 public:
  GnBlock(int64_t latent, int hidden_layers);
  BlockLatents forward(const BlockLatents& in, const TypedGraph& graph) override;
  double flops(int64_t nodes, int64_t edges) const override;

 private:
  Mlp edge_mlp_{nullptr}, node_mlp_{nullptr};
};

}  // namespace gnn
