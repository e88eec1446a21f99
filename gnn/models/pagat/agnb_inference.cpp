// AGNB inference on the CPU without autograd (AgnbBlock::forward_in_chunks): the same function as
// AgnbBlock::forward in fewer passes over the edges. The plain path spends most of a frame on
// passes over [E, L] tensors that each do little (gathers, bias copies, BatchNorm, ReLU,
// LayerNorm, per-type index_selects, the softmax's shifts and divisions), at L = 32 for the
// student, where a matrix product of a chunk costs no more than a pass over it. Here
//  - the edge MLP, its 1x1 convolution and BatchNorm (one affine map in eval mode, folded), and
//    the edge message MLP run in row chunks that stay in cache (row_chunks.h), writing e' and
//    the messages;
//  - phi_A and every edge's attention score (the edge projections of all four link types in
//    one product, the node projections gathered, the physics bias added) run in a second chunked
//    pass, writing phi_A [E, L] and the scores [E, heads];
//  - the softmax per link type and receiver, the mean over heads and the weighted sums of the
//    four aggregates are one pass per receiver (the edges are sorted by receiver), with no
//    per-type copies of the edges;
//  - what acts on the n node rows (an eighth of the edge rows) stays plain LibTorch.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>

#include "gnn/models/pagat/agnb_block.h"
#include "gnn/models/row_chunks.h"

namespace gnn {

namespace {

constexpr int64_t kNodeChunk = 256;  // node rows per chunk

// y = x W^T + b.
struct Affine {
  torch::Tensor weight, bias;
};

// An MLP's last Linear, then a Linear, then BatchNorm with its running statistics: with no
// activation between them, one affine map.
Affine fold_into_one_map(const torch::nn::Linear& last, const torch::nn::Linear& conv,
                         const torch::nn::BatchNorm1d& bn) {
  const auto scale = bn->weight / torch::sqrt(bn->running_var + bn->options.eps());  // [L]
  const auto weight = scale.unsqueeze(1) * torch::mm(conv->weight, last->weight);
  const auto bias =
      scale * (torch::mv(conv->weight, last->bias) + conv->bias - bn->running_mean) + bn->bias;
  return {weight.contiguous(), bias.contiguous()};
}

// An MLP (no LayerNorm) on the rows `in` [rows, L], into `out`; x and y are scratch of the shape
// [rows, L] (every hidden width of the block's MLPs is L).
void mlp_rows(MlpImpl& mlp, const torch::Tensor& in, torch::Tensor x, torch::Tensor y,
              torch::Tensor out) {
  const int64_t rows = in.size(0);
  auto first = mlp.first();
  at::mm_out(x, in, first->weight.t());
  add_bias_relu(x.data_ptr<float>(), first->bias.data_ptr<float>(), rows, x.size(1));
  const size_t last = mlp.linears() - 1;
  for (size_t l = 1; l < last; ++l) {
    auto layer = mlp.linear(l);
    at::mm_out(y, x, layer->weight.t());
    add_bias_relu(y.data_ptr<float>(), layer->bias.data_ptr<float>(), rows, y.size(1));
    std::swap(x, y);
  }
  at::mm_out(out, x, mlp.linear(last)->weight.t());
  add_bias(out.data_ptr<float>(), mlp.linear(last)->bias.data_ptr<float>(), rows, out.size(1));
}

// The hidden layers of an MLP after its first (activated in `x`), ending with x holding the
// last hidden layer's activated output.
torch::Tensor hidden_rows(MlpImpl& mlp, torch::Tensor x, torch::Tensor y) {
  for (size_t l = 1; l + 1 < mlp.linears(); ++l) {
    auto layer = mlp.linear(l);
    at::mm_out(y, x, layer->weight.t());
    add_bias_relu(y.data_ptr<float>(), layer->bias.data_ptr<float>(), x.size(0), y.size(1));
    std::swap(x, y);
  }
  return x;
}

// The rows of the weights of four Linears stacked ([4 L, L]), and their biases (zeros where a
// Linear has none).
torch::Tensor stacked_weights(const std::array<torch::nn::Linear, kLinkTypes>& layers) {
  std::vector<torch::Tensor> w;
  for (const auto& l : layers) w.push_back(l->weight);
  return torch::cat(w, 0).contiguous();
}

torch::Tensor stacked_biases(const std::array<torch::nn::Linear, kLinkTypes>& layers) {
  std::vector<torch::Tensor> b;
  for (const auto& l : layers)
    b.push_back(l->bias.defined() ? l->bias : torch::zeros({l->weight.size(0)}));
  return torch::cat(b, 0).contiguous();
}

// Node rows run in chunks too, side by side: on n rows of L = 32 floats each LibTorch operation
// is short enough that splitting every one of them over the threads costs more than it saves.
template <class Body>
void for_node_chunks(int64_t n, const Body& body) {
  const int64_t chunks = (n + kNodeChunk - 1) / kNodeChunk;
  for_chunks(chunks, [&](int64_t first_chunk, int64_t last_chunk, int) {
    torch::NoGradGuard no_grad;
    for (int64_t c = first_chunk; c < last_chunk; ++c)
      body(c * kNodeChunk, std::min(n, (c + 1) * kNodeChunk));
  });
}

// What the attention scores of a chunk of edges read: the edges' link types and ends, e', the
// edge projections W_T,e of the four link types stacked [4L, L], every node's source and target
// projections [n, 8L] and the a_T vectors [4, heads, width].
struct AttentionInputs {
  const int64_t *link, *senders, *receivers;
  torch::Tensor e1, edge_weights, attention_parts, attention_vectors;
  int64_t L, heads;
};

// A thread's scratch for the scores of one chunk.
struct ScoreScratch {
  explicit ScoreScratch(int64_t L)
      : grouped(torch::empty({kChunk, L})),
        grouped_projection(torch::empty({kChunk, L})),
        row_of(kChunk),
        weighted(static_cast<size_t>(L)) {}
  // The chunk's e' rows grouped by link type, and their edge projections W_T,e e'.
  torch::Tensor grouped, grouped_projection;
  std::vector<int64_t> row_of;  // chunk row -> its row in `grouped`
  std::vector<float> weighted;
};

// Scores of edges c0 .. c0 + rows into s [rows, heads]: a_T . LeakyReLU(W_T,src h_b +
// W_T,dst h_a + W_T,e e'_ab) per head.
void score_chunk(const AttentionInputs& in, ScoreScratch& scratch, int64_t c0, int64_t rows,
                 float* s) {
  const int64_t* link = in.link;
  const int64_t* senders = in.senders;
  const int64_t* receivers = in.receivers;
  const int64_t L = in.L, heads = in.heads, width = L / heads;
  const torch::Tensor& e1 = in.e1;
  const torch::Tensor& edge_weights = in.edge_weights;
  const torch::Tensor& attention_parts = in.attention_parts;
  const torch::Tensor& attention_vectors = in.attention_vectors;
  torch::Tensor& grouped = scratch.grouped;
  torch::Tensor& grouped_projection = scratch.grouped_projection;
  std::vector<int64_t>& row_of = scratch.row_of;
  std::vector<float>& weighted = scratch.weighted;
  int64_t start[kLinkTypes + 1] = {0, 0, 0, 0, 0};
  for (int64_t r = 0; r < rows; ++r) ++start[link[c0 + r] + 1];
  for (int64_t t = 0; t < kLinkTypes; ++t) start[t + 1] += start[t];
  int64_t next[kLinkTypes] = {start[0], start[1], start[2], start[3]};
  const float* e1_data = e1.data_ptr<float>() + c0 * L;
  float* g_data = grouped.data_ptr<float>();
  for (int64_t r = 0; r < rows; ++r) {
    row_of[size_t(r)] = next[link[c0 + r]]++;
    std::copy(e1_data + r * L, e1_data + (r + 1) * L, g_data + row_of[size_t(r)] * L);
  }
  for (int64_t t = 0; t < kLinkTypes; ++t)
    if (start[t + 1] > start[t]) {
      auto out = grouped_projection.slice(0, start[t], start[t + 1]);
      at::mm_out(out, grouped.slice(0, start[t], start[t + 1]),
                 edge_weights.slice(0, t * L, (t + 1) * L).t());
    }
  const float* p = grouped_projection.data_ptr<float>();
  const float* parts = attention_parts.data_ptr<float>();
  const float* vectors = attention_vectors.data_ptr<float>();
  float* w = weighted.data();
  for (int64_t r = 0; r < rows; ++r) {
    const int64_t k = c0 + r, t = link[k];
    const float* pe = p + row_of[size_t(r)] * L;
    const float* ps = parts + senders[k] * 8 * L + t * L;
    const float* pr = parts + receivers[k] * 8 * L + (kLinkTypes + t) * L;
    const float* a_t = vectors + t * L;
#pragma omp simd
    for (int64_t j = 0; j < L; ++j) {
      const float zj = pe[j] + ps[j] + pr[j];
      w[j] = a_t[j] * (zj > 0 ? zj : 0.2f * zj);
    }
    for (int64_t head = 0; head < heads; ++head) {
      float sum = 0;
      for (int64_t j = head * width; j < (head + 1) * width; ++j) sum += w[j];
      s[r * heads + head] = sum;
    }
  }
}

// Per receiver: the softmax over its edges of each link type (per head), the heads' mean and
// the weighted sums of the messages (phi_A * phi_A for ST), into `aggregated` [n, 4L].
void aggregate_by_receiver(const TypedGraph& g, const torch::Tensor& score,
                           const torch::Tensor& phi, int64_t heads, int64_t L,
                           torch::Tensor& aggregated) {
  const int64_t n = aggregated.size(0);
  const int64_t* link = g.link_type.data_ptr<int64_t>();
  const int64_t* offsets = g.order.offsets.data_ptr<int64_t>();
  const float* s = score.data_ptr<float>();
  const float* m = phi.data_ptr<float>();
  float* out = aggregated.data_ptr<float>();
  at::parallel_for(0, n, 64, [&](int64_t begin, int64_t end) {
    std::vector<float> largest(size_t(kLinkTypes * heads)), total(largest.size());
    for (int64_t i = begin; i < end; ++i) {
      std::fill(largest.begin(), largest.end(), -std::numeric_limits<float>::infinity());
      std::fill(total.begin(), total.end(), 0.0f);
      for (int64_t k = offsets[i]; k < offsets[i + 1]; ++k)
        for (int64_t head = 0; head < heads; ++head) {
          float& l = largest[size_t(link[k] * heads + head)];
          l = std::max(l, s[k * heads + head]);
        }
      for (int64_t k = offsets[i]; k < offsets[i + 1]; ++k)
        for (int64_t head = 0; head < heads; ++head) {
          const size_t slot = size_t(link[k] * heads + head);
          total[slot] += std::exp(s[k * heads + head] - largest[slot]);
        }
      float* row = out + i * kLinkTypes * L;
      for (int64_t k = offsets[i]; k < offsets[i + 1]; ++k) {
        const int64_t t = link[k];
        float alpha = 0;
        for (int64_t head = 0; head < heads; ++head) {
          const size_t slot = size_t(t * heads + head);
          alpha += std::exp(s[k * heads + head] - largest[slot]) / total[slot];
        }
        alpha /= float(heads);
        const float* mk = m + k * L;
        float* o = row + t * L;
        if (t == kLinkST) {
#pragma omp simd
          for (int64_t c = 0; c < L; ++c) o[c] += alpha * mk[c] * mk[c];
        } else {
#pragma omp simd
          for (int64_t c = 0; c < L; ++c) o[c] += alpha * mk[c];
        }
      }
    }
  });
}

}  // namespace

bool AgnbBlock::can_run_in_chunks(const BlockLatents& in, const TypedGraph& g) const {
  return !torch::GradMode::is_enabled() && !is_training() && g.order.canonical &&
         g.link_type.defined() && in.nodes.is_cpu() && in.nodes.scalar_type() == torch::kFloat32 &&
         in.edges.scalar_type() == torch::kFloat32 &&
         (!g.physics_bias.defined() || g.physics_bias.scalar_type() == torch::kFloat32);
}

struct AgnbBlock::EdgePass {
  torch::Tensor e1, message, e_out;  // e', its messages and the new edge latents e + e'
};

struct AgnbBlock::NodePass {
  torch::Tensor h;
  torch::Tensor phi_receiver, phi_sender;         // phi_A's first layer's parts [n, L] each
  torch::Tensor attention_parts;                  // [n, 8L] with content attention, else undefined
  torch::Tensor attention_vectors, edge_weights;  // the same
};

// 1. Position-aware module: e' (and the new edge latents e + e') and the edge messages.
AgnbBlock::EdgePass AgnbBlock::edge_pass(const torch::Tensor& v, const torch::Tensor& e,
                                         const TypedGraph& g) {
  const int64_t E = e.size(0), L = latent_;
  const auto projected = edge_nodes_->forward(v);  // [n, 2L]: receiver part | sender part
  auto first = edge_mlp_->first();
  const auto receiver_part = (projected.slice(1, 0, L) + first->bias).contiguous();
  const auto sender_part = projected.slice(1, L, 2 * L).contiguous();
  const Affine to_e1 =
      fold_into_one_map(edge_mlp_->linear(edge_mlp_->linears() - 1), edge_conv_, edge_bn_);
  auto e1 = torch::empty({E, L}), message = torch::empty({E, L}), e_out = torch::empty({E, L});
  for_chunks(chunk_count(E), [&](int64_t first_chunk, int64_t last_chunk, int) {
    torch::NoGradGuard no_grad;  // grad mode is per thread
    auto a = torch::empty({kChunk, L}), b = torch::empty({kChunk, L});
    for (int64_t c = first_chunk; c < last_chunk; ++c) {
      const int64_t c0 = c * kChunk, c1 = std::min(E, c0 + kChunk), rows = c1 - c0;
      auto x = a.slice(0, 0, rows), y = b.slice(0, 0, rows);
      edge_first_layer_chunk(x, receiver_part, sender_part, g.order, e, first->weight, c0);
      x = hidden_rows(*edge_mlp_, x, y);
      auto e1_rows = e1.slice(0, c0, c1);
      at::mm_out(e1_rows, x, to_e1.weight.t());
      add_bias(e1_rows.data_ptr<float>(), to_e1.bias.data_ptr<float>(), rows, L);
      auto e_rows = e_out.slice(0, c0, c1);
      at::add_out(e_rows, e.slice(0, c0, c1), e1_rows);
      mlp_rows(*edge_message_, e1_rows, a.slice(0, 0, rows), b.slice(0, 0, rows),
               message.slice(0, c0, c1));
    }
  });
  return {e1, message, e_out};
}

// The node state h, and what the edges read of it: phi_A's first layer's parts [n, 2L]
// (receiver | sender, the layer's bias on the receiver's) and, with the learned scores, every
// link type's source and target projections [n, 8L] (W_T,src h for T = ST .. BD, then
// W_T,dst h + its bias).
AgnbBlock::NodePass AgnbBlock::node_pass(const torch::Tensor& v, const torch::Tensor& summed) {
  const int64_t n = v.size(0), L = latent_;
  auto phi_first = phi_a_->first();
  const auto phi_weights = phi_a_nodes_->weight;
  const auto phi_bias = torch::cat({phi_first->bias, torch::zeros({L})});
  torch::Tensor attention_weights, attention_bias, attention_vectors, edge_weights;
  if (content_attention_) {
    attention_weights = torch::cat({stacked_weights(source_), stacked_weights(target_)}, 0);
    attention_bias = torch::cat({stacked_biases(source_), stacked_biases(target_)});
    attention_vectors =
        torch::stack(std::vector<torch::Tensor>(attention_.begin(), attention_.end()))
            .contiguous();                  // [4, heads, width]: link type t's a_T from t L on
    edge_weights = stacked_weights(edge_);  // [4L, L]: link type t's W_T,e in rows t L ..
  }
  auto h = torch::empty({n, L}), phi_parts = torch::empty({n, 2 * L});
  auto attention_parts = content_attention_ ? torch::empty({n, 8 * L}) : torch::Tensor();
  for_node_chunks(n, [&](int64_t r0, int64_t r1) {
    const auto vr = v.slice(0, r0, r1);
    auto hr = h.slice(0, r0, r1);
    at::add_out(hr, node_bn_->forward(node_conv_->forward(node_mlp_->forward(vr))),
                summed.slice(0, r0, r1));
    hr.add_(velocity_bn_->forward(velocity_conv_->forward(velocity_mlp_->forward(vr))));
    hr.add_(velocity_skip_->forward(vr));
    auto phi_rows = phi_parts.slice(0, r0, r1);
    at::addmm_out(phi_rows, phi_bias, hr, phi_weights.t());
    if (content_attention_) {
      auto attention_rows = attention_parts.slice(0, r0, r1);
      at::addmm_out(attention_rows, attention_bias, hr, attention_weights.t());
    }
  });
  const auto phi_receiver = phi_parts.slice(1, 0, L).contiguous();
  const auto phi_sender = phi_parts.slice(1, L, 2 * L).contiguous();
  NodePass out;
  out.h = h;
  out.phi_receiver = phi_receiver;
  out.phi_sender = phi_sender;
  out.attention_parts = attention_parts;
  out.attention_vectors = attention_vectors;
  out.edge_weights = edge_weights;
  return out;
}

// 2-3. phi_A [E, L] and the attention scores [E, heads], per edge, the physics bias added.
std::pair<torch::Tensor, torch::Tensor> AgnbBlock::message_pass(const EdgePass& edges,
                                                                const NodePass& nodes,
                                                                const TypedGraph& g) {
  const torch::Tensor& e1 = edges.e1;
  const int64_t E = e1.size(0), L = latent_, heads = heads_;
  const torch::Tensor& phi_receiver = nodes.phi_receiver;
  const torch::Tensor& phi_sender = nodes.phi_sender;
  auto phi_first = phi_a_->first();
  const AttentionInputs attention{g.link_type.data_ptr<int64_t>(),
                                  g.order.senders.data_ptr<int64_t>(),
                                  g.order.receivers.data_ptr<int64_t>(),
                                  e1,
                                  nodes.edge_weights,
                                  nodes.attention_parts,
                                  nodes.attention_vectors,
                                  L,
                                  heads};
  MlpImpl& phi_mlp = *phi_a_->mlp();
  auto phi_norm = phi_a_->norm();
  const auto no_bias = torch::zeros({L});
  const auto bias = g.physics_bias.defined() ? g.physics_bias.contiguous() : torch::Tensor();
  auto phi = torch::empty({E, L}), score = torch::zeros({E, heads});
  for_chunks(chunk_count(E), [&](int64_t first_chunk, int64_t last_chunk, int) {
    torch::NoGradGuard no_grad;
    auto a = torch::empty({kChunk, L}), b = torch::empty({kChunk, L});
    std::optional<ScoreScratch> scratch;
    if (content_attention_) scratch.emplace(L);
    for (int64_t c = first_chunk; c < last_chunk; ++c) {
      const int64_t c0 = c * kChunk, c1 = std::min(E, c0 + kChunk), rows = c1 - c0;
      auto x = a.slice(0, 0, rows), y = b.slice(0, 0, rows);
      // phi_A = LN(ReLU(MLP([e', h_a, h_b]))).
      edge_first_layer_chunk(x, phi_receiver, phi_sender, g.order, e1, phi_first->weight, c0);
      x = hidden_rows(phi_mlp, x, y);
      auto last = phi_mlp.linear(phi_mlp.linears() - 1);
      auto z = (x.data_ptr() == a.data_ptr() ? b : a).slice(0, 0, rows);
      at::mm_out(z, x, last->weight.t());
      add_bias_relu(z.data_ptr<float>(), last->bias.data_ptr<float>(), rows, L);
      add_bias_layer_norm(z.data_ptr<float>(), no_bias.data_ptr<float>(),
                          phi_norm->weight.data_ptr<float>(), phi_norm->bias.data_ptr<float>(),
                          phi_norm->options.eps(), phi.data_ptr<float>() + c0 * L, rows, L);
      // Scores: a_T . LeakyReLU(W_T,src h_b + W_T,dst h_a + W_T,e e'_ab) per head, + bias.
      float* s = score.data_ptr<float>() + c0 * heads;
      if (content_attention_) score_chunk(attention, *scratch, c0, rows, s);
      if (bias.defined()) {
        const float* pb = bias.data_ptr<float>() + c0 * heads;
        for (int64_t j = 0; j < rows * heads; ++j) s[j] += pb[j];
      }
    }
  });
  return {phi, score};
}

// The four aggregations' phi_B and 4., the node update with its residual.
torch::Tensor AgnbBlock::node_update_pass(const torch::Tensor& v, const torch::Tensor& h,
                                          const torch::Tensor& aggregated) {
  const int64_t n = v.size(0), L = latent_;
  auto v_out = torch::empty({n, L});
  for_node_chunks(n, [&](int64_t r0, int64_t r1) {
    const auto hr = h.slice(0, r0, r1);
    const auto rows = aggregated.slice(0, r0, r1);
    auto typed = [&](int64_t t) { return rows.slice(1, t * L, (t + 1) * L); };
    const auto sta = phi_b_[kLinkST]->forward(torch::cat({hr, typed(kLinkST)}, 1));
    const auto spa = phi_b_[kLinkSP]->forward(torch::cat({typed(kLinkSP), hr}, 1));
    auto dpa = phi_b_[kLinkDP]->forward(torch::cat({hr, typed(kLinkDP)}, 1));
    dpa = dpa + dp_outer_->forward(dp_norm_->forward(dp_inner_->forward(dpa)));
    const auto bd = phi_b_[kLinkBD]->forward(torch::cat({typed(kLinkBD), hr}, 1));
    auto v_rows = v_out.slice(0, r0, r1);
    at::add_out(v_rows, v.slice(0, r0, r1),
                update_->forward(torch::cat({hr, sta, spa, dpa, bd}, 1)));
  });
  return v_out;
}

BlockLatents AgnbBlock::forward_in_chunks(const BlockLatents& in, const TypedGraph& g) {
  const auto v = in.nodes.contiguous(), e = in.edges.contiguous();
  const EdgePass edges = edge_pass(v, e, g);
  const auto summed = csr_sum_by_receiver(edges.message, g.order);  // [n, L]
  const NodePass nodes = node_pass(v, summed);
  const auto [phi, score] = message_pass(edges, nodes, g);
  auto aggregated = torch::zeros({v.size(0), kLinkTypes * latent_});
  aggregate_by_receiver(g, score, phi, heads_, latent_, aggregated);
  return {node_update_pass(v, nodes.h, aggregated), edges.e_out};
}

}  // namespace gnn
