#pragma once
// Row chunks for the fused CPU passes of GNS (inference in gns_model.cpp, training in
// gns_processor_step.cpp), of DPI-Nets (inference in dpi_inference.cpp) and of PAGATNet's AGNB
// blocks (inference in pagat/agnb_inference.cpp): an MLP's intermediates for one chunk of rows
// (kChunk x latent floats) stay in the core's L2 cache between its matrix products and its
// element-wise passes.

#include <torch/torch.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

#include "gnn/graph/segment_ops.h"
#include "gnn/models/mlp.h"
#include "gnn/runtime/runtime.h"

namespace gnn {

constexpr int64_t kChunk = 1024;  // rows per chunk

inline int64_t chunk_count(int64_t rows) {
  return (rows + kChunk - 1) / kChunk;
}

// Runs body(first, last, thread) over the chunks [0, chunks): side by side on the LibTorch
// threads when BLAS is single-threaded, else on this thread (thread 0), each product then using
// BLAS's own threads (products issued from several threads into a multi-threaded BLAS would
// fight over the cores).
template <class Body>
void for_chunks(int64_t chunks, const Body& body) {
  if (blas_threads() <= 1 && at::get_num_threads() > 1)
    at::parallel_for(0, chunks, 1,
                     [&](int64_t first, int64_t last) { body(first, last, at::get_thread_num()); });
  else
    body(int64_t(0), chunks, 0);
}

// rows x width, in place: x = max(x + bias, 0).
inline void add_bias_relu(float* x, const float* bias, int64_t rows, int64_t width) {
  for (int64_t r = 0; r < rows; ++r, x += width)
#pragma omp simd
    for (int64_t c = 0; c < width; ++c) x[c] = std::max(x[c] + bias[c], 0.0f);
}

// out = x + bias row by row, in place.
inline void add_bias(float* x, const float* bias, int64_t rows, int64_t width) {
  for (int64_t r = 0; r < rows; ++r, x += width)
#pragma omp simd
    for (int64_t c = 0; c < width; ++c) x[c] += bias[c];
}

// out[r] = a[ia[r]] + b[ib[r]] for rows of `width` floats: both gathers and their sum in one pass.
inline void gather_pair_sum(const float* a, const float* b, const int64_t* ia, const int64_t* ib,
                            float* out, int64_t rows, int64_t width) {
  for (int64_t r = 0; r < rows; ++r, out += width) {
    const float* x = a + ia[r] * width;
    const float* y = b + ib[r] * width;
    for (int64_t c = 0; c < width; ++c) out[c] = x[c] + y[c];
  }
}

// An MLP's first layer on [e_ij, v_i, v_j] for the edge rows c0 .. c0 + x.size(0), in place in
// `x` [rows, width]: relu(receiver_part[receiver] + sender_part[sender] + edges W^T), the node
// parts projected per node beforehand (receiver_part carrying the layer's bias) - the first
// step of GNS's and DPI-Nets' fused edge passes.
inline void edge_first_layer_chunk(torch::Tensor& x, const torch::Tensor& receiver_part,
                                   const torch::Tensor& sender_part, const EdgeOrder& order,
                                   const torch::Tensor& edges, const torch::Tensor& weight,
                                   int64_t c0) {
  const int64_t rows = x.size(0);
  gather_pair_sum(receiver_part.data_ptr<float>(), sender_part.data_ptr<float>(),
                  order.receivers.data_ptr<int64_t>() + c0, order.senders.data_ptr<int64_t>() + c0,
                  x.data_ptr<float>(), rows, x.size(1));
  x.addmm_(edges.slice(0, c0, c0 + rows), weight.t());
  x.relu_();
}

// LayerNorm's statistics of one row of x + bias: its mean and 1 / its standard deviation.
inline std::pair<float, float> layer_norm_statistics(const float* x, const float* bias,
                                                     int64_t width, float eps) {
  // omp simd: lets the compiler vectorise the sums (it may not reorder float additions
  // otherwise).
  float mean = 0;
#pragma omp simd reduction(+ : mean)
  for (int64_t c = 0; c < width; ++c) mean += x[c] + bias[c];
  mean /= float(width);
  float var = 0;
#pragma omp simd reduction(+ : var)
  for (int64_t c = 0; c < width; ++c) {
    const float d = x[c] + bias[c] - mean;
    var += d * d;
  }
  return {mean, 1.0f / std::sqrt(var / float(width) + eps)};
}

// out = LayerNorm(x + bias) row by row, in one pass over x (no autograd).
// With `accumulate` the result is added to `out` (a residual), otherwise written to it.
inline void add_bias_layer_norm(const float* x, const float* bias, const float* gamma,
                                const float* beta, double eps, float* out, int64_t rows,
                                int64_t width, bool accumulate = false) {
  for (int64_t r = 0; r < rows; ++r, x += width, out += width) {
    const auto [mean, inv] = layer_norm_statistics(x, bias, width, float(eps));
    if (accumulate)
      for (int64_t c = 0; c < width; ++c)
        out[c] += (x[c] + bias[c] - mean) * inv * gamma[c] + beta[c];
    else
      for (int64_t c = 0; c < width; ++c)
        out[c] = (x[c] + bias[c] - mean) * inv * gamma[c] + beta[c];
  }
}

// The rest of an MLP on one chunk of rows: `x` holds its first layer's activated output, `y` is
// scratch of the same shape; the LayerNorm'ed result is written to `out` (added with
// `accumulate`).
inline void finish_mlp_chunk(MlpImpl& mlp, torch::Tensor x, torch::Tensor y, float* out,
                             bool accumulate) {
  const int64_t rows = x.size(0), width = x.size(1);
  auto norm = mlp.norm();
  for (size_t l = 1; l < mlp.linears(); ++l) {
    auto layer = mlp.linear(l);
    at::mm_out(y, x, layer->weight.t());
    if (l + 1 < mlp.linears()) {
      add_bias_relu(y.data_ptr<float>(), layer->bias.data_ptr<float>(), rows, width);
      std::swap(x, y);
    } else {
      add_bias_layer_norm(y.data_ptr<float>(), layer->bias.data_ptr<float>(),
                          norm->weight.data_ptr<float>(), norm->bias.data_ptr<float>(),
                          norm->options.eps(), out, rows, width, accumulate);
    }
  }
}

}  // namespace gnn
