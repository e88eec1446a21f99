#include "gnn/models/dpi_model.h"

#include <stdexcept>

#include "common/config_visitors.h"

namespace gnn {

namespace {

torch::nn::Linear linear(int64_t in, int64_t out, bool bias) {
  return torch::nn::Linear(torch::nn::LinearOptions(in, out).bias(bias));
}

}  // namespace

DpiModel::DpiModel(const DpiConfig& config) : config_(config) {
  const int64_t P = config.particle_width, R = config.relation_width, F = config.effect_width;
  const int64_t state = kNodeFeatures + config.input.type_embedding;
  const int H = config.encoder_hidden_layers;
  type_embedding_ = register_module("type_embedding",
                                    torch::nn::Embedding(kNodeTypes, config.input.type_embedding));
  particle_encoder_ = register_module("particle_encoder", Mlp(state, P, P, H, false));
  relation_encoder_ = register_module("relation_encoder", Mlp(kEdgeFeatures, R, R, H, false));
  relation_nodes_ = register_module("relation_nodes", linear(state, 2 * R, false));
  relation_code_ = register_module("relation_code", linear(R, F, true));
  relation_effects_ = register_module("relation_effects", linear(F, 2 * F, false));
  particle_code_ = register_module("particle_code", linear(P, F, true));
  particle_sum_ = register_module("particle_sum", linear(F, F, false));
  particle_self_ = register_module("particle_self", linear(F, F, false));
  decoder_ = register_module("decoder", Mlp(F, F, kModelOutputs, 1, false));
}

torch::Tensor DpiModel::next_velocity(const GraphInput& g) {
  check_graph_input(g, "dpi next_velocity");
  return propagate(g, nullptr, nullptr).slice(1, 0, 3);
}

torch::Tensor DpiModel::propagate(const GraphInput& g, std::vector<torch::Tensor>* node_latents,
                                  std::vector<torch::Tensor>* edge_latents) {
  const int64_t R = config_.relation_width, F = config_.effect_width, n = g.nodes();
  const EdgeOrder order = edge_order(g.edge_index, n);
  if (!node_latents && !edge_latents && can_propagate_in_chunks(g, order))
    return propagate_in_chunks(g, order);

  // Encoders. s: [n, kNodeFeatures + type_embedding]
  const auto s = torch::cat({g.node_features, type_embedding_->forward(g.node_type)}, 1);
  const auto particle = torch::relu(particle_encoder_->forward(s));  // c_i [n, P]
  torch::Tensor relation;                                            // c_ij [E, R]
  {
    const auto nodes = relation_nodes_->forward(s);  // [n, 2R]: sender part | receiver part
    auto h = relation_encoder_->first()->forward(g.edge_features);
    h.add_(gather_senders(nodes.slice(1, 0, R), order));
    h.add_(gather_receivers(nodes.slice(1, R, 2 * R), order));
    relation = torch::relu(relation_encoder_->forward_after_first(h));
  }

  // Propagation. The parts on the encodings (and the biases) are the same in every step.
  const auto relation_part = relation_code_->forward(relation);  // [E, F]
  const auto particle_part = particle_code_->forward(particle);  // [n, F]
  auto effect = torch::zeros({n, F}, particle_part.options());   // h^0 [n, F]
  for (int l = 0; l < config_.propagation_steps; ++l) {
    torch::Tensor e;  // e^l [E, F]
    if (l == 0) {
      e = torch::relu(relation_part);  // h^0 = 0: the effect parts vanish
    } else {
      const auto projected = relation_effects_->forward(effect);  // [n, 2F]: receiver | sender
      e = relation_part + gather_receivers(projected.slice(1, 0, F), order) +
          gather_senders(projected.slice(1, F, 2 * F), order);
      e = torch::relu(e);
    }
    const auto summed = sum_to_receivers(e, order, n);  // [n, F]
    auto update = particle_part + particle_sum_->forward(summed);
    if (l > 0) update = update + particle_self_->forward(effect);
    effect = effect + torch::relu(update);
    if (node_latents) node_latents->push_back(effect);
    if (edge_latents) edge_latents->push_back(e);
  }
  return decoder_->forward(effect);
}

ModelOutput DpiModel::run(const GraphInput& g, const ForwardOptions& options) {
  if (!velocity_scale_.defined())
    throw std::logic_error(
        "dpi: no normalisation statistics to turn the predicted velocity into an acceleration "
        "(use the model through a LearnedSimulator, or call set_normalisation)");
  ModelOutput out;
  const auto decoded = propagate(g, options.keep_latents ? &out.node_latents : nullptr,
                                 options.keep_latents ? &out.edge_latents : nullptr);  // [n, 4]
  const auto u = decoded.slice(1, 0, 3);
  out.oil_fraction_change = decoded.select(1, 3);
  const auto last = g.node_features.slice(1, kLastVelocityColumn, kLastVelocityColumn + 3);
  const auto device = u.device();
  out.acceleration =
      (u - last) * velocity_scale_.to(device) + acceleration_offset_.to(device);  // [n, 3]
  return out;
}

double DpiModel::flops(int64_t nodes, int64_t edges) const {
  auto linear_flops = [](const torch::nn::Linear& l) {
    return 2.0 * double(l->weight.size(0) * l->weight.size(1));
  };
  const double n = double(nodes), e = double(edges), steps = config_.propagation_steps;
  // Encoders (the relation encoder's node parts as per-node projections, see the header).
  double f = n * (particle_encoder_->flops_per_row() + linear_flops(relation_nodes_)) +
             e * relation_encoder_->flops_per_row();
  // The propagators' parts on the encodings, once.
  f += e * linear_flops(relation_code_) + n * linear_flops(particle_code_);
  // Per step: the sum's projection; after the first, the effect projections and the self term.
  f += steps * n * linear_flops(particle_sum_) +
       (steps - 1) * n * (linear_flops(relation_effects_) + linear_flops(particle_self_));
  return f + n * decoder_->flops_per_row();
}

void DpiModel::set_normalisation(const Normalisation& n) {
  velocity_scale_ = (n.vel_std / n.acc_std).to(torch::kFloat32);
  acceleration_offset_ = (-n.acc_mean / n.acc_std).to(torch::kFloat32);
}

std::shared_ptr<GraphModel> DpiModel::from_config(const nlohmann::json& config,
                                                  const std::string& file) {
  DpiConfig c;
  common::JsonReader::read_struct(config, file, "", c);
  return std::make_shared<DpiModel>(c);
}

nlohmann::json DpiModel::config() const {
  return common::JsonWriter::write_struct(config_);
}

}  // namespace gnn
