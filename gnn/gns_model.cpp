#include "gnn/gns_model.h"

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
  for (size_t k = 1; k < layers_.size(); ++k) x = layers_[k]->forward(torch::relu(x));
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

torch::Tensor GnsModel::forward(const GraphInput& g) {
  const int64_t L = config_.latent;
  auto v = node_encoder_->forward(
      torch::cat({g.node_features, type_embedding_->forward(g.node_type)}, 1));
  auto e = edge_encoder_->forward(g.edge_features);
  const auto senders = g.edge_index[0], receivers = g.edge_index[1];
  for (size_t k = 0; k < edge_mlp_.size(); ++k) {
    // Edge update from [e_ij, v_receiver, v_sender] with the first layer split per node.
    auto projected = receiver_sender_[k]->forward(v);  // [n, 2L]
    auto h = edge_mlp_[k]->first()->forward(e);
    h = h + projected.slice(1, 0, L).index_select(0, receivers) +
        projected.slice(1, L, 2 * L).index_select(0, senders);
    auto e_update = edge_mlp_[k]->forward_after_first(h);
    auto aggregated = torch::zeros({g.nodes(), L}, v.options()).index_add_(0, receivers, e_update);
    auto v_update = node_mlp_[k]->forward_after_first(node_mlp_[k]->first()->forward(v) +
                                                      aggregate_[k]->forward(aggregated));
    e = e + e_update;
    v = v + v_update;
  }
  return decoder_->forward(v);
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
