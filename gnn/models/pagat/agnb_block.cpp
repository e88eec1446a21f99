#include "gnn/models/pagat/agnb_block.h"

#include <string>

namespace gnn {

namespace {

const char* const kLinkNames[kLinkTypes] = {"st", "sp", "dp", "bd"};

torch::nn::Linear linear(int64_t in, int64_t out, bool bias) {
  return torch::nn::Linear(torch::nn::LinearOptions(in, out).bias(bias));
}

double linear_flops(const torch::nn::Linear& l) {
  return 2.0 * double(l->weight.numel());
}

}  // namespace

TypedGraph typed_graph(const torch::Tensor& edge_index, const torch::Tensor& link_type,
                       int64_t nodes) {
  TypedGraph g;
  g.nodes = nodes;
  g.order = edge_order(edge_index, nodes);
  const auto cpu_types = edges_by_link_type(link_type.cpu(), edge_index[1].cpu(), nodes);
  const auto device = edge_index.device();
  g.link_type = link_type.to(torch::kInt64).contiguous();
  for (size_t t = 0; t < size_t(kLinkTypes); ++t) {
    g.types[t] = {cpu_types[t].edges.to(device), cpu_types[t].offsets.to(device)};
    g.receivers[t] = edge_index[1].index_select(0, g.types[t].edges);
    g.senders[t] = edge_index[0].index_select(0, g.types[t].edges);
  }
  return g;
}

NormalisedMlpImpl::NormalisedMlpImpl(int64_t in, int64_t width, int hidden_layers) {
  mlp_ = register_module("mlp", Mlp(in, width, width, hidden_layers, false));
  norm_ = register_module("norm", torch::nn::LayerNorm(torch::nn::LayerNormOptions({width})));
}

torch::Tensor NormalisedMlpImpl::forward(const torch::Tensor& x) {
  return norm_->forward(torch::relu(mlp_->forward(x)));
}

torch::Tensor NormalisedMlpImpl::forward_after_first(const torch::Tensor& pre) {
  return norm_->forward(torch::relu(mlp_->forward_after_first(pre)));
}

AgnbBlock::AgnbBlock(int64_t L, int64_t heads, int H, bool content_attention)
    : latent_(L), heads_(heads), content_attention_(content_attention) {
  edge_mlp_ = register_module("edge_mlp", Mlp(L, L, L, H, false));
  edge_nodes_ = register_module("edge_nodes", linear(L, 2 * L, false));
  edge_conv_ = register_module("edge_conv", linear(L, L, true));
  edge_bn_ = register_module("edge_bn", torch::nn::BatchNorm1d(L));
  edge_message_ = register_module("edge_message", Mlp(L, L, L, H, false));
  node_mlp_ = register_module("node_mlp", Mlp(L, L, L, H, false));
  node_conv_ = register_module("node_conv", linear(L, L, true));
  node_bn_ = register_module("node_bn", torch::nn::BatchNorm1d(L));
  velocity_mlp_ = register_module("velocity_mlp", Mlp(L, L, L, H, false));
  velocity_conv_ = register_module("velocity_conv", linear(L, L, true));
  velocity_bn_ = register_module("velocity_bn", torch::nn::BatchNorm1d(L));
  velocity_skip_ = register_module("velocity_skip", Mlp(L, L, L, H, false));
  for (size_t t = 0; t < size_t(kLinkTypes); ++t) {
    const std::string name = kLinkNames[t];
    if (content_attention) {
      source_[t] = register_module("attention_" + name + "_source", linear(L, L, false));
      target_[t] = register_module("attention_" + name + "_target", linear(L, L, true));
      edge_[t] = register_module("attention_" + name + "_edge", linear(L, L, false));
      attention_[t] = register_parameter("attention_" + name + "_vector",
                                         torch::randn({heads, L / heads}) / std::sqrt(double(L)));
    }
    phi_b_[t] = register_module("phi_b_" + name, NormalisedMlp(2 * L, L, H));
  }
  phi_a_ = register_module("phi_a", NormalisedMlp(L, L, H));
  phi_a_nodes_ = register_module("phi_a_nodes", linear(L, 2 * L, false));
  dp_inner_ = register_module("dp_inner", Mlp(L, L, L, H, false));
  dp_norm_ = register_module("dp_norm", torch::nn::LayerNorm(torch::nn::LayerNormOptions({L})));
  dp_outer_ = register_module("dp_outer", Mlp(L, L, L, H, false));
  update_ = register_module("update", Mlp(5 * L, L, L, H, true));
}

torch::Tensor AgnbBlock::batch_norm(torch::nn::BatchNorm1d& bn, const torch::Tensor& x) {
  if (x.size(0) > 1 || !is_training()) return bn->forward(x);
  return torch::batch_norm(x, bn->weight, bn->bias, bn->running_mean, bn->running_var,
                           /*training=*/false, 0.0, bn->options.eps(), /*cudnn_enabled=*/false);
}

torch::Tensor AgnbBlock::scores(size_t t, const torch::Tensor& h, const torch::Tensor& e1,
                                const TypedGraph& g) {
  const auto& idx = g.types[t].edges;
  const int64_t L = latent_;
  torch::Tensor score;
  if (content_attention_) {
    const auto z = torch::leaky_relu(source_[t]->forward(h).index_select(0, g.senders[t]) +
                                         target_[t]->forward(h).index_select(0, g.receivers[t]) +
                                         edge_[t]->forward(e1.index_select(0, idx)),
                                     0.2);
    score = (z.view({-1, heads_, L / heads_}) * attention_[t]).sum(2);
  } else {
    score = torch::zeros({idx.size(0), heads_}, h.options());
  }
  if (g.physics_bias.defined()) score = score + g.physics_bias.index_select(0, idx);
  return score;
}

BlockLatents AgnbBlock::forward(const BlockLatents& in, const TypedGraph& g) {
  if (can_run_in_chunks(in, g)) return forward_in_chunks(in, g);
  const auto& v = in.nodes;
  const auto& e = in.edges;
  const int64_t n = v.size(0), L = latent_;

  // Row k of [W_a x | W_b x] gathered: the receiver's part and the sender's part of a first
  // layer on [e_ab, x_a, x_b].
  auto node_parts = [&](torch::nn::Linear& projection, const torch::Tensor& x) {
    const auto p = projection->forward(x);  // [n, 2L]
    return gather_receivers(p.slice(1, 0, L), g.order) +
           gather_senders(p.slice(1, L, 2 * L), g.order);
  };

  // 1. Position-aware module.
  const auto e1 =
      batch_norm(edge_bn_, edge_conv_->forward(edge_mlp_->forward_after_first(
                               edge_mlp_->first()->forward(e) + node_parts(edge_nodes_, v))));
  const auto v1 = batch_norm(node_bn_, node_conv_->forward(node_mlp_->forward(v))) +
                  sum_to_receivers(edge_message_->forward(e1), g.order, n);
  const auto u1 = batch_norm(velocity_bn_, velocity_conv_->forward(velocity_mlp_->forward(v))) +
                  velocity_skip_->forward(v);
  const auto h = v1 + u1;

  // 2-3. Attention and messages per link type.
  const auto phi_a = phi_a_->forward_after_first(phi_a_->first()->forward(e1) +
                                                 node_parts(phi_a_nodes_, h));  // [E, L]
  std::array<torch::Tensor, kLinkTypes> aggregated;
  for (size_t t = 0; t < size_t(kLinkTypes); ++t) {
    const auto& typed = g.types[t];
    if (typed.edges.numel() == 0) {
      aggregated[t] = torch::zeros({n, L}, v.options());
      continue;
    }
    const auto idx = typed.edges;
    const auto alpha =
        segment_softmax(scores(t, h, e1, g), g.receivers[t], typed.offsets).mean(1, true);
    auto message = phi_a.index_select(0, idx);
    if (int64_t(t) == kLinkST) message = message * message;  // the attention-gated product
    aggregated[t] = segment_sum(alpha * message, g.receivers[t], typed.offsets);  // [n, L]
  }
  const auto sta = phi_b_[kLinkST]->forward(torch::cat({h, aggregated[kLinkST]}, 1));
  const auto spa = phi_b_[kLinkSP]->forward(torch::cat({aggregated[kLinkSP], h}, 1));
  auto dpa = phi_b_[kLinkDP]->forward(torch::cat({h, aggregated[kLinkDP]}, 1));
  dpa = dpa + dp_outer_->forward(dp_norm_->forward(dp_inner_->forward(dpa)));
  const auto bd = phi_b_[kLinkBD]->forward(torch::cat({aggregated[kLinkBD], h}, 1));

  // 4. Residual updates.
  return {v + update_->forward(torch::cat({h, sta, spa, dpa, bd}, 1)), e + e1};
}

double AgnbBlock::flops(int64_t nodes, int64_t edges) const {
  const double n = double(nodes), E = double(edges);
  double f = E * (edge_mlp_->flops_per_row() + linear_flops(edge_conv_) +
                  edge_message_->flops_per_row() + phi_a_->flops_per_row());
  f += n * (linear_flops(edge_nodes_) + linear_flops(phi_a_nodes_) + node_mlp_->flops_per_row() +
            linear_flops(node_conv_) + velocity_mlp_->flops_per_row() +
            linear_flops(velocity_conv_) + velocity_skip_->flops_per_row() +
            dp_inner_->flops_per_row() + dp_outer_->flops_per_row() + update_->flops_per_row());
  // Each edge is of one type: its attention's edge projection; every node runs the four types'
  // source and target projections and the four phi_B.
  if (content_attention_) f += E * linear_flops(edge_[0]);
  for (size_t t = 0; t < size_t(kLinkTypes); ++t) {
    f += n * phi_b_[t]->flops_per_row();
    if (content_attention_) f += n * (linear_flops(source_[t]) + linear_flops(target_[t]));
  }
  return f;
}

GnBlock::GnBlock(int64_t L, int H) {
  edge_mlp_ = register_module("edge_mlp", Mlp(3 * L, L, L, H, true));
  node_mlp_ = register_module("node_mlp", Mlp(2 * L, L, L, H, true));
}

BlockLatents GnBlock::forward(const BlockLatents& in, const TypedGraph& g) {
  const auto& v = in.nodes;
  const auto update = edge_mlp_->forward(
      torch::cat({in.edges, gather_receivers(v, g.order), gather_senders(v, g.order)}, 1));
  const auto messages = sum_to_receivers(update, g.order, v.size(0));
  return {v + node_mlp_->forward(torch::cat({v, messages}, 1)), in.edges + update};
}

double GnBlock::flops(int64_t nodes, int64_t edges) const {
  return double(edges) * edge_mlp_->flops_per_row() + double(nodes) * node_mlp_->flops_per_row();
}

}  // namespace gnn
