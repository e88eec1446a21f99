#include "gnn/models/gns_model.h"

#include <algorithm>
#include <cmath>
#include <tuple>

#include "common/config_visitors.h"
#include "gnn/graph/segment_ops.h"
#include "gnn/models/gns_processor_step.h"
#include "gnn/models/row_chunks.h"

namespace gnn {

GnsModel::GnsModel(const GnsConfig& config) : config_(config) {
  const int64_t L = config.latent;
  const int H = config.mlp_hidden_layers;
  type_embedding_ = register_module("type_embedding",
                                    torch::nn::Embedding(kNodeTypes, config.input.type_embedding));
  node_encoder_ = register_module("node_encoder",
                                  Mlp(kNodeFeatures + config.input.type_embedding, L, L, H, true));
  edge_encoder_ = register_module("edge_encoder", Mlp(kEdgeFeatures, L, L, H, true));
  for (int k = 0; k < config.layers; ++k) {
    const std::string s = std::to_string(k);
    edge_mlp_.push_back(register_module("edge_mlp" + s, Mlp(L, L, L, H, true)));
    receiver_sender_.push_back(
        register_module("edge_receiver_sender" + s,
                        torch::nn::Linear(torch::nn::LinearOptions(L, 2 * L).bias(false))));
    node_mlp_.push_back(register_module("node_mlp" + s, Mlp(L, L, L, H, true)));
    aggregate_.push_back(register_module(
        "node_aggregate" + s, torch::nn::Linear(torch::nn::LinearOptions(L, L).bias(false))));
  }
  decoder_ = register_module("decoder", Mlp(L, L, kModelOutputs, H, false));
}

GnsModel::Latents GnsModel::encode(const GraphInput& g) {
  return {node_encoder_->forward(
              torch::cat({g.node_features, type_embedding_->forward(g.node_type)}, 1)),
          edge_encoder_->forward(g.edge_features)};
}

GnsModel::Latents GnsModel::process(Latents x, const GraphInput& g,
                                    std::vector<torch::Tensor>* node_latents,
                                    std::vector<torch::Tensor>* edge_latents) {
  const int64_t L = config_.latent;
  auto v = x.nodes, e = x.edges;
  const EdgeOrder order = edge_order(g.edge_index, g.nodes());
  // Without autograd the residual sums overwrite the latents (copies: the caller's stay intact).
  // The fused CPU kernels of that path read raw float32 memory; elsewhere (a GPU) the plain
  // products below serve both cases.
  const bool in_place = !torch::GradMode::is_enabled() && v.is_cpu();
  // After each layer, when asked: a copy on the in-place path, which overwrites v and e.
  auto keep = [&] {
    if (node_latents) node_latents->push_back(in_place ? v.clone() : v);
    if (edge_latents) edge_latents->push_back(in_place ? e.clone() : e);
  };
  if (in_place) {
    v = v.clone();
    e = e.clone();
  }
  for (size_t k = 0; k < edge_mlp_.size(); ++k) {
    if (in_place) {
      // Inference: every product in row chunks (see edge_update_in_chunks).
      auto projected = rows_times_transposed(v, receiver_sender_[k]->weight);  // [n, 2L]
      auto e_update = edge_update_in_chunks(k, e, projected, order);
      auto aggregated = sum_to_receivers(e_update, order, g.nodes());
      node_update_in_chunks(k, v, aggregated);
      e.add_(e_update);
      keep();
      continue;
    }
    if (lean_backward_ && order.canonical && v.is_cpu() && v.scalar_type() == torch::kFloat32) {
      // Training on the CPU: the same step with a hand-written backward (gns_processor_step.h).
      std::tie(v, e) = processor_step_with_lean_backward(v, e, *edge_mlp_[k], *receiver_sender_[k],
                                                         *node_mlp_[k], *aggregate_[k], order);
      keep();
      continue;
    }
    // Edge update from [e_ij, v_receiver, v_sender] with the first layer split per node.
    auto projected = receiver_sender_[k]->forward(v);  // [n, 2L]
    torch::Tensor e_update;
    {
      auto h = edge_mlp_[k]->first()->forward(e);
      h.add_(gather_receivers(projected.slice(1, 0, L), order));
      h.add_(gather_senders(projected.slice(1, L, 2 * L), order));
      e_update = edge_mlp_[k]->forward_after_first(h);
    }
    auto aggregated = sum_to_receivers(e_update, order, g.nodes());
    auto node_in = node_mlp_[k]->first()->forward(v);
    node_in.add_(aggregate_[k]->forward(aggregated));
    auto v_update = node_mlp_[k]->forward_after_first(node_in);
    e = e + e_update;
    v = v + v_update;
    keep();
  }
  return {v, e};
}

torch::Tensor GnsModel::rows_times_transposed(const torch::Tensor& x_in, const torch::Tensor& w) {
  auto x = x_in.contiguous();
  auto out = torch::empty({x.size(0), w.size(0)}, x.options());
  const int64_t rows = x.size(0);
  for_chunks(chunk_count(rows), [&](int64_t first, int64_t last, int) {
    torch::NoGradGuard no_grad;
    for (int64_t c = first; c < last; ++c) {
      auto o = out.slice(0, c * kChunk, std::min(rows, (c + 1) * kChunk));
      at::mm_out(o, x.slice(0, c * kChunk, std::min(rows, (c + 1) * kChunk)), w.t());
    }
  });
  return out;
}

void GnsModel::node_update_in_chunks(size_t k, torch::Tensor& v, const torch::Tensor& aggregated) {
  const int64_t L = config_.latent, n = v.size(0);
  Mlp& mlp = node_mlp_[k];
  auto agg = aggregated.contiguous();
  for_chunks(chunk_count(n), [&](int64_t first, int64_t last, int) {
    torch::NoGradGuard no_grad;
    auto a = torch::empty({kChunk, L}), b = torch::empty({kChunk, L});
    for (int64_t c = first; c < last; ++c) {
      const int64_t c0 = c * kChunk, c1 = std::min(n, c0 + kChunk), rows = c1 - c0;
      auto x = a.slice(0, 0, rows), y = b.slice(0, 0, rows);
      at::mm_out(x, v.slice(0, c0, c1), mlp->first()->weight.t());
      x.addmm_(agg.slice(0, c0, c1), aggregate_[k]->weight.t());
      add_bias_relu(x.data_ptr<float>(), mlp->first()->bias.data_ptr<float>(), rows, L);
      // The residual: v += LayerNorm(...), in the same pass. Rows of v are read above only by
      // this chunk, so updating them here is safe.
      finish_mlp_chunk(*mlp, x, y, v.data_ptr<float>() + c0 * L, /*accumulate=*/true);
    }
  });
}

torch::Tensor GnsModel::edge_update_in_chunks(size_t k, const torch::Tensor& e,
                                              const torch::Tensor& projected,
                                              const EdgeOrder& order) {
  const int64_t L = config_.latent, E = e.size(0);
  // Rows per chunk (kChunk): the MLP's intermediates of one chunk (kChunk x L floats each) stay
  // in the core's L2 cache between the matrix products and the element-wise passes.
  Mlp& mlp = edge_mlp_[k];
  // The first layer's bias is added once per node (to the receiver projection), not per edge.
  auto receiver_part = (projected.slice(1, 0, L) + mlp->first()->bias).contiguous();
  auto sender_part = projected.slice(1, L, 2 * L).contiguous();
  auto edges = e.contiguous();
  auto out = torch::empty_like(e);
  // Chunks run side by side on the LibTorch threads, each op inside single-threaded (LibTorch
  // runs nested ops serially) and BLAS on one thread (spill-infer's runtime setting), so the
  // cores never wait on each other's small operations. Matrix products write into per-thread
  // buffers; bias, ReLU and LayerNorm are fused into single passes.
  for_chunks(chunk_count(E), [&](int64_t first, int64_t last, int) {
    torch::NoGradGuard no_grad;  // grad mode is per thread
    auto a = torch::empty({kChunk, L}), b = torch::empty({kChunk, L});
    for (int64_t c = first; c < last; ++c) {
      const int64_t c0 = c * kChunk, c1 = std::min(E, c0 + kChunk), rows = c1 - c0;
      auto x = a.slice(0, 0, rows), y = b.slice(0, 0, rows);
      edge_first_layer_chunk(x, receiver_part, sender_part, order, edges, mlp->first()->weight, c0);
      finish_mlp_chunk(*mlp, x, y, out.data_ptr<float>() + c0 * L, /*accumulate=*/false);
    }
  });
  return out;
}

torch::Tensor GnsModel::decode(const Latents& x) {
  return decoder_->forward(x.nodes);
}

ModelOutput GnsModel::run(const GraphInput& g, const ForwardOptions& options) {
  ModelOutput out;
  const Latents latents = process(encode(g), g, options.keep_latents ? &out.node_latents : nullptr,
                                  options.keep_latents ? &out.edge_latents : nullptr);
  const auto decoded = decode(latents);  // [n, 4]
  out.acceleration = decoded.slice(1, 0, 3);
  out.oil_fraction_change = decoded.select(1, 3);
  return out;
}

std::shared_ptr<GraphModel> GnsModel::from_config(const nlohmann::json& config,
                                                  const std::string& file) {
  GnsConfig c;
  common::JsonReader::read_struct(config, file, "", c);
  return std::make_shared<GnsModel>(c);
}

double GnsModel::flops(int64_t nodes, int64_t edges) const {
  return double(nodes) * (node_encoder_->flops_per_row() + decoder_->flops_per_row()) +
         double(edges) * edge_encoder_->flops_per_row() + processor_flops(nodes, edges);
}

double GnsModel::processor_flops(int64_t nodes, int64_t edges) const {
  const double L = config_.latent, H = config_.mlp_hidden_layers;
  // Per step: edge MLP (first layer on e, then H more L x L layers) and the node projections
  // [n, L] x [L, 2L]; node MLP (first layer on v and on the aggregate, then H more).
  const double edge = double(edges) * (1 + H) * L * L + double(nodes) * 2 * L * L;
  const double node = double(nodes) * (2 + H) * L * L;
  return 2.0 * config_.layers * (edge + node);
}

nlohmann::json GnsModel::config() const {
  return common::JsonWriter::write_struct(config_);
}

}  // namespace gnn
