#include "gnn/gns_model.h"

#include "gnn/segment_ops.h"
#include "sph/config_visitors.h"

namespace gnn {

MlpImpl::MlpImpl(int64_t in, int64_t hidden, int64_t out, int hidden_layers, bool layer_norm) {
  int64_t width = in;
  for (int k = 0; k <= hidden_layers; ++k) {
    const int64_t next = k == hidden_layers ? out : hidden;
    layers_.push_back(
        register_module("linear" + std::to_string(k), torch::nn::Linear(width, next)));
    width = next;
  }
  if (layer_norm)
    norm_ = register_module("norm", torch::nn::LayerNorm(torch::nn::LayerNormOptions({out})));
}

torch::Tensor MlpImpl::forward_after_first(torch::Tensor x) {
  // relu_ in place: the Linear before it does not need its output for the backward pass.
  for (size_t k = 1; k < layers_.size(); ++k) x = layers_[k]->forward(torch::relu_(x));
  return norm_ ? norm_->forward(x) : x;
}

torch::Tensor MlpImpl::forward(torch::Tensor x) {
  return forward_after_first(layers_[0]->forward(x));
}

GnsModel::GnsModel(const GnsConfig& config) : config_(config) {
  const int64_t L = config.latent;
  const int H = config.mlp_hidden_layers;
  type_embedding_ =
      register_module("type_embedding", torch::nn::Embedding(kNodeTypes, config.type_embedding));
  node_encoder_ =
      register_module("node_encoder", Mlp(kNodeFeatures + config.type_embedding, L, L, H, true));
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
  decoder_ = register_module("decoder", Mlp(L, L, 3, H, false));
}

GnsModel::Latents GnsModel::encode(const GraphInput& g) {
  return {node_encoder_->forward(
              torch::cat({g.node_features, type_embedding_->forward(g.node_type)}, 1)),
          edge_encoder_->forward(g.edge_features)};
}

GnsModel::Latents GnsModel::process(Latents x, const GraphInput& g) {
  const int64_t L = config_.latent;
  auto v = x.nodes, e = x.edges;
  const EdgeOrder order = edge_order(g.edge_index, g.nodes());
  // Without autograd the residual sums can overwrite their inputs.
  const bool in_place = !torch::GradMode::is_enabled();
  for (size_t k = 0; k < edge_mlp_.size(); ++k) {
    // Edge update from [e_ij, v_receiver, v_sender] with the first layer split per node.
    auto projected = receiver_sender_[k]->forward(v);  // [n, 2L]
    torch::Tensor e_update;
    if (in_place) {
      e_update = edge_update_in_chunks(k, e, projected, order);
    } else {
      auto h = edge_mlp_[k]->first()->forward(e);
      h.add_(gather_receivers(projected.slice(1, 0, L), order));
      h.add_(gather_senders(projected.slice(1, L, 2 * L), order));
      e_update = edge_mlp_[k]->forward_after_first(h);
    }
    auto aggregated = sum_to_receivers(e_update, order, g.nodes());
    auto node_in = node_mlp_[k]->first()->forward(v);
    node_in.add_(aggregate_[k]->forward(aggregated));
    auto v_update = node_mlp_[k]->forward_after_first(node_in);
    e = in_place ? e.add_(e_update) : e + e_update;
    v = in_place ? v.add_(v_update) : v + v_update;
  }
  return {v, e};
}

torch::Tensor GnsModel::edge_update_in_chunks(size_t k, const torch::Tensor& e,
                                              const torch::Tensor& projected,
                                              const EdgeOrder& order) {
  const int64_t L = config_.latent, E = e.size(0);
  // Rows per chunk: the MLP's intermediates of one chunk (kChunk x L floats each) stay in the
  // core's L2 cache between the matrix products and the element-wise passes.
  constexpr int64_t kChunk = 1024;
  auto receiver_part = projected.slice(1, 0, L), sender_part = projected.slice(1, L, 2 * L);
  auto out = torch::empty_like(e);
  for (int64_t c0 = 0; c0 < E; c0 += kChunk) {
    const int64_t c1 = std::min(E, c0 + kChunk);
    auto h = edge_mlp_[k]->first()->forward(e.slice(0, c0, c1));
    h.add_(receiver_part.index_select(0, order.receivers.slice(0, c0, c1)));
    h.add_(sender_part.index_select(0, order.senders.slice(0, c0, c1)));
    out.slice(0, c0, c1).copy_(edge_mlp_[k]->forward_after_first(h));
  }
  return out;
}

torch::Tensor GnsModel::decode(const Latents& x) {
  return decoder_->forward(x.nodes);
}

torch::Tensor GnsModel::forward(const GraphInput& g) {
  return decode(process(encode(g), g));
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
  return sph::JsonWriter::write_struct(config_);
}

std::shared_ptr<GraphModel> make_model(const nlohmann::json& config, const std::string& file) {
  if (!config.is_object()) throw sph::ConfigError(file, "", "expected a JSON object");
  if (!config.contains("model") || !config["model"].is_string())
    throw sph::ConfigError(file, "/model", "missing the model name (one of: gns)");
  const std::string name = config["model"].get<std::string>();
  if (name == "gns") {
    GnsConfig c;
    sph::JsonReader::read_struct(config, file, "", c);
    return std::make_shared<GnsModel>(c);
  }
  throw sph::ConfigError(file, "/model", "unknown model \"" + name + "\" (known: gns)");
}

}  // namespace gnn
