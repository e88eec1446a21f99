#pragma once
// One GNS interaction-network step for training, with a hand-written backward.
//
// Through LibTorch's autograd a step keeps every intermediate of its MLPs (the Linear inputs,
// the ReLU outputs, the LayerNorm inputs and statistics, the gathered node projections) and its
// backward runs one generic operation per node of the graph. This step computes the same
// function in a few fused passes and keeps only what its backward reads:
//   - per MLP, the outputs of its ReLUs (each Linear's input after the first; the ReLU's mask is
//     where they are positive) and the LayerNorm's normalised values and 1/std per row;
//   - the step's inputs v, e and the aggregated messages.
// The backward is the chain rule written out over the same pieces: LayerNorm backward per row,
// each Linear's weight and input gradients as matrix products, the receiver and sender
// projections' gradients as CSR sums by receiver and by sender (the edges of sender i are the
// reverses of the edges of receiver i), and the residuals passed through.
//
// Both passes run over chunks of 1,024 rows (edges or nodes), as the inference path does: a
// chunk's activations and gradients stay in the core's L2 cache between its matrix products
// and its element-wise passes (bias, ReLU and its mask, LayerNorm), which are fused. With BLAS
// on one thread the chunks run side by side on the LibTorch threads, each thread summing its
// own weight gradients; with more BLAS threads they run in turn and each product uses them.
// Measured (docs/benchmarks.md, "Training"): a GNS-10-128 step on a 4,096-particle lattice takes
// 2.95 s against 6.57 s through autograd and 6.41 s in the tuned plain-PyTorch reference.
//
// The step is the one GnsModel::process computes (gns_model.h): edge update
//   e' = LN(MLP_e(W_e e_ij + (W_r v)_receiver + (W_s v)_sender)), messages summed to receivers,
//   v' = LN(MLP_v(W_v v_i + W_a sum_j e'_ij)), and the outputs v + v', e + e'.

#include <utility>

#include "gnn/graph/segment_ops.h"
#include "gnn/models/mlp.h"

namespace gnn {

// {v + v', e + e'} for float32 CPU tensors and a canonical edge order (edge_order()).
std::pair<torch::Tensor, torch::Tensor> processor_step_with_lean_backward(
    const torch::Tensor& v, const torch::Tensor& e, MlpImpl& edge_mlp,
    torch::nn::LinearImpl& receiver_sender, MlpImpl& node_mlp, torch::nn::LinearImpl& aggregate,
    const EdgeOrder& order);

}  // namespace gnn
