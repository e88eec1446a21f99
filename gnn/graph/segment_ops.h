#pragma once
// Gathers and sums over the edges of a graph whose edges are sorted by receiver and which holds
// every edge in both directions (the radius graph is symmetric). With that order, summing the
// messages to each receiver is a pass over contiguous rows (a CSR sum, parallel over receivers
// with no atomics), and the backward passes of both gathers are CSR sums too: the gradient of a
// gather by sender is a gather by receiver of the reversed edges. LibTorch's index_add_ (the
// backward of index_select, and the usual scatter) serialises over edges on the CPU.

#include <torch/torch.h>

namespace gnn {

struct EdgeOrder {
  torch::Tensor senders, receivers;  // [E] int64
  torch::Tensor offsets;             // [n + 1]: edges of receiver i are offsets[i] .. offsets[i+1]
  torch::Tensor reverse;             // [E]: the index of edge (r -> s) for edge (s -> r)
  bool canonical = false;            // sorted by receiver and symmetric: the fast path applies
};

EdgeOrder edge_order(const torch::Tensor& edge_index, int64_t nodes);

// values[receivers], values[senders] and the per-receiver sum of edge rows, each with the
// CSR backward when order.canonical and the tensors are float32 on the CPU (plain index_select /
// index_add_ otherwise, e.g. on a GPU).
torch::Tensor gather_receivers(const torch::Tensor& values, const EdgeOrder& order);
torch::Tensor gather_senders(const torch::Tensor& values, const EdgeOrder& order);
torch::Tensor sum_to_receivers(const torch::Tensor& edge_values, const EdgeOrder& order,
                               int64_t nodes);

// Softmax of `scores` [R, H] (H heads) over each receiver's rows, for rows listed receiver by
// receiver: receiver i's rows are offsets[i] .. offsets[i+1] and receivers[r] is row r's
// receiver ([R] int64, offsets [n + 1]) - the edges of one link type in TypedEdges' order
// (heterogeneous_typing.h) for PAGATNet's attention. With autograd; the per-segment maximum it
// subtracts for stability is a constant to it (softmax does not change under a shift).
torch::Tensor segment_softmax(const torch::Tensor& scores, const torch::Tensor& receivers,
                              const torch::Tensor& offsets);

// Per-receiver sums of `values` [R, W] for rows listed receiver by receiver as above: out[i] is
// the sum of rows offsets[i] .. offsets[i+1] ([n, W]). With autograd (the backward gathers by
// `receivers`).
torch::Tensor segment_sum(const torch::Tensor& values, const torch::Tensor& receivers,
                          const torch::Tensor& offsets);

// Without autograd, for a canonical order and float32 CPU rows (hand-written backward passes):
// out[i] = sum of the rows of `edge_values` whose receiver is i (resp. whose sender is i).
torch::Tensor csr_sum_by_receiver(const torch::Tensor& edge_values, const EdgeOrder& order);
torch::Tensor csr_sum_by_sender(const torch::Tensor& edge_values, const EdgeOrder& order);

}  // namespace gnn
