#include "gnn/models/pagat_model.h"

#include <stdexcept>

#include "common/config_error.h"
#include "common/config_visitors.h"

namespace gnn {

PagatModel::PagatModel(const PagatConfig& config) : config_(config) {
  const int64_t L = config.latent;
  const int H = config.mlp_hidden_layers;
  if (L % config.heads != 0)
    throw std::invalid_argument("pagat: latent " + std::to_string(L) +
                                " is not a multiple of heads " + std::to_string(config.heads));
  type_embedding_ = register_module("type_embedding",
                                    torch::nn::Embedding(kNodeTypes, config.input.type_embedding));
  node_encoder_ = register_module("node_encoder",
                                  Mlp(kNodeFeatures + config.input.type_embedding, L, L, H, true));
  edge_encoder_ = register_module("edge_encoder", Mlp(kEdgeFeatures, L, L, H, true));
  const bool agnb = config.processor == "agnb";
  if (agnb && config.physics_aware)
    physics_ = register_module("physics", PhysicsModule(config.physics_width, config.heads));
  for (int k = 0; k < config.blocks; ++k) {
    std::shared_ptr<ProcessorBlock> block;
    if (agnb)
      block = std::make_shared<AgnbBlock>(L, config.heads, H, config.attention);
    else
      block = std::make_shared<GnBlock>(L, H);
    blocks_.push_back(register_module("block" + std::to_string(k), block));
  }
  decoder_ = register_module("decoder", Mlp(L, L, kModelOutputs, H, false));
  class_head_ = register_module("class_head", torch::nn::Linear(L, kFluidNodeClasses));
  for (int k = 0; k < (config.teacher_latent > 0 ? config.blocks : 0); ++k) {
    const auto options = torch::nn::LinearOptions(config.teacher_latent, L).bias(false);
    node_adapters_.push_back(
        register_module("node_adapter" + std::to_string(k), torch::nn::Linear(options)));
    edge_adapters_.push_back(
        register_module("edge_adapter" + std::to_string(k), torch::nn::Linear(options)));
  }
}

torch::Tensor PagatModel::adapt_nodes(size_t block, const torch::Tensor& teacher_nodes) {
  return node_adapters_.at(block)->forward(teacher_nodes);
}

torch::Tensor PagatModel::adapt_edges(size_t block, const torch::Tensor& teacher_edges) {
  return edge_adapters_.at(block)->forward(teacher_edges);
}

torch::Tensor PagatModel::class_logits(const torch::Tensor& node_latents) {
  return class_head_->forward(node_latents);
}

ModelOutput PagatModel::run(const GraphInput& g, const ForwardOptions& options) {
  if (!g.node_class.defined() || !g.link_type.defined())
    throw std::invalid_argument(
        "pagat: the graph has no heterogeneous typing (node_class, link_type); build it with "
        "LearnedSimulator::encode");
  TypedGraph typed = typed_graph(g.edge_index, g.link_type, g.nodes());
  if (physics_) typed.physics_bias = physics_->forward(relation_vectors(g));
  BlockLatents x{node_encoder_->forward(
                     torch::cat({g.node_features, type_embedding_->forward(g.node_type)}, 1)),
                 edge_encoder_->forward(g.edge_features)};
  ModelOutput out;
  for (size_t k = 0; k < blocks_.size(); ++k) {
    x = blocks_[k]->forward(x, typed);
    if (options.keep_latents) {
      out.node_latents.push_back(x.nodes);
      out.edge_latents.push_back(x.edges);
    }
    if (options.after_layer) options.after_layer(k, x.nodes, x.edges);
  }
  const auto decoded = decoder_->forward(x.nodes);
  out.acceleration = decoded.slice(1, 0, 3);
  out.oil_fraction_change = decoded.select(1, 3);
  out.auxiliary["node_class_logits"] = class_head_->forward(x.nodes);
  return out;
}

double PagatModel::flops(int64_t nodes, int64_t edges) const {
  double f = double(nodes) * (node_encoder_->flops_per_row() + decoder_->flops_per_row() +
                              2.0 * double(class_head_->weight.numel())) +
             double(edges) * edge_encoder_->flops_per_row();
  if (physics_) f += double(edges) * physics_->flops_per_edge();
  for (const auto& block : blocks_) f += block->flops(nodes, edges);
  return f;
}

std::shared_ptr<GraphModel> PagatModel::from_config(const nlohmann::json& config,
                                                    const std::string& file) {
  PagatConfig c;
  common::JsonReader::read_struct(config, file, "", c);
  if (c.latent % c.heads != 0)
    throw common::ConfigError(file, "/latent",
                              "must be a multiple of heads (" + std::to_string(c.heads) + ")");
  if (c.processor == "gn" && c.physics_aware)
    throw common::ConfigError(file, "/physics_aware",
                              "the gn processor has no attention scores to bias: set it false "
                              "with \"processor\": \"gn\"");
  return std::make_shared<PagatModel>(c);
}

nlohmann::json upgrade_stored_pagat_config(nlohmann::json stored) {
  if (!stored.is_object()) return stored;
  if (!stored.contains("surface_rule")) stored["surface_rule"] = "kernel_sum";
  if (stored.contains("processor")) return stored;
  const bool plain_blocks = !stored.value("attention", true);
  stored["processor"] = plain_blocks ? "gn" : "agnb";
  if (plain_blocks) stored["physics_aware"] = false;
  return stored;
}

nlohmann::json PagatModel::config() const {
  return common::JsonWriter::write_struct(config_);
}

}  // namespace gnn
