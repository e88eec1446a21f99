// DPI-Nets inference on the CPU without autograd (DpiModel::propagate_in_chunks): the same
// function as DpiModel::propagate, in fewer passes over the edges. The plain path materialises
// several [E, width] tensors per propagation step (two gathers, their sums, the ReLU, then the
// sum to receivers), each a full pass over memory, and that, not the matrix products, is where a
// frame's time went (DPI-Nets took 1.8x GNS's forward time at a quarter of its parameters). Here
//  - the relation encoder and the propagator's part on the relation codes run in row chunks
//    that stay in cache (row_chunks.h), with the node projections gathered in the same pass,
//    and write one [E, effect] tensor, the only edge-sized one;
//  - each propagation step is one pass over it: receiver by receiver (the edges are sorted by
//    receiver), relu(code_ij + receiver part_i + sender part_j) is summed straight into the
//    receiver's row, in the edge order sum_to_receivers uses.
#include <algorithm>

#include "gnn/models/dpi_model.h"
#include "gnn/models/row_chunks.h"

namespace gnn {

bool DpiModel::can_propagate_in_chunks(const GraphInput& g, const EdgeOrder& order) const {
  return !torch::GradMode::is_enabled() && order.canonical && g.edge_features.is_cpu() &&
         g.edge_features.scalar_type() == torch::kFloat32 &&
         g.node_features.scalar_type() == torch::kFloat32;
}

torch::Tensor DpiModel::propagate_in_chunks(const GraphInput& g, const EdgeOrder& order) {
  const int64_t R = config_.relation_width, F = config_.effect_width, n = g.nodes(), E = g.edges();
  const auto s = torch::cat({g.node_features, type_embedding_->forward(g.node_type)}, 1);
  const auto particle = torch::relu(particle_encoder_->forward(s));  // c_i [n, P]

  // Relation codes, folded straight into the propagator's part on them: [E, F].
  auto first = relation_encoder_->first();
  const auto nodes = relation_nodes_->forward(s);  // [n, 2R]: sender part | receiver part
  const auto sender_part = nodes.slice(1, 0, R).contiguous();
  const auto receiver_part = (nodes.slice(1, R, 2 * R) + first->bias).contiguous();  // + bias once
  const auto edge_features = g.edge_features.contiguous();
  auto relation_part = torch::empty({E, F});
  for_chunks(chunk_count(E), [&](int64_t first_chunk, int64_t last_chunk, int) {
    torch::NoGradGuard no_grad;  // grad mode is per thread
    auto a = torch::empty({kChunk, R}), b = torch::empty({kChunk, R});
    for (int64_t c = first_chunk; c < last_chunk; ++c) {
      const int64_t c0 = c * kChunk, c1 = std::min(E, c0 + kChunk), rows = c1 - c0;
      auto x = a.slice(0, 0, rows), y = b.slice(0, 0, rows);
      edge_first_layer_chunk(x, receiver_part, sender_part, order, edge_features, first->weight,
                             c0);
      // The encoder's other layers, each followed by a ReLU (the last one by the ReLU of c_ij).
      for (size_t l = 1; l < relation_encoder_->linears(); ++l) {
        auto layer = relation_encoder_->linear(l);
        at::mm_out(y, x, layer->weight.t());
        add_bias_relu(y.data_ptr<float>(), layer->bias.data_ptr<float>(), rows, R);
        std::swap(x, y);
      }
      auto out = relation_part.slice(0, c0, c1);
      at::mm_out(out, x, relation_code_->weight.t());
      add_bias(out.data_ptr<float>(), relation_code_->bias.data_ptr<float>(), rows, F);
    }
  });

  // Propagation, one pass over the edges per step.
  const auto particle_part = particle_code_->forward(particle);  // [n, F]
  auto effect = torch::zeros({n, F});
  const float* code = relation_part.data_ptr<float>();
  const int64_t* offsets = order.offsets.data_ptr<int64_t>();
  const int64_t* senders = order.senders.data_ptr<int64_t>();
  for (int l = 0; l < config_.propagation_steps; ++l) {
    torch::Tensor receiver_effect, sender_effect;  // [n, F] each, from the step before
    if (l > 0) {
      const auto projected = relation_effects_->forward(effect);  // [n, 2F]: receiver | sender
      receiver_effect = projected.slice(1, 0, F).contiguous();
      sender_effect = projected.slice(1, F, 2 * F).contiguous();
    }
    auto summed = torch::zeros({n, F});
    float* sum = summed.data_ptr<float>();
    const float* to = l > 0 ? receiver_effect.data_ptr<float>() : nullptr;
    const float* from = l > 0 ? sender_effect.data_ptr<float>() : nullptr;
    at::parallel_for(0, n, 64, [&](int64_t begin, int64_t end) {
      for (int64_t i = begin; i < end; ++i) {
        float* out = sum + i * F;
        for (int64_t k = offsets[i]; k < offsets[i + 1]; ++k) {
          const float* c_ij = code + k * F;
          if (l == 0) {  // h^0 = 0: the effect parts vanish
#pragma omp simd
            for (int64_t c = 0; c < F; ++c) out[c] += std::max(c_ij[c], 0.0f);
          } else {
            const float* r = to + i * F;
            const float* t = from + senders[k] * F;
#pragma omp simd
            for (int64_t c = 0; c < F; ++c) out[c] += std::max(c_ij[c] + r[c] + t[c], 0.0f);
          }
        }
      }
    });
    auto update = particle_part + particle_sum_->forward(summed);
    if (l > 0) update = update + particle_self_->forward(effect);
    effect = effect + torch::relu(update);
  }
  return decoder_->forward(effect);
}

}  // namespace gnn
