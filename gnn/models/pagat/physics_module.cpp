#include "gnn/models/pagat/physics_module.h"

#include "gnn/graph/heterogeneous_typing.h"

namespace gnn {

torch::Tensor relation_vectors(const GraphInput& g) {
  const auto senders = g.edge_index[0], receivers = g.edge_index[1];
  auto difference = [&](const torch::Tensor& node_values) {
    return node_values.index_select(0, senders) - node_values.index_select(0, receivers);
  };
  const auto velocity = g.node_features.slice(1, kLastVelocityColumn, kLastVelocityColumn + 3);
  const auto material = g.node_features.slice(1, kVelocityFeatures, kVelocityFeatures + 2);
  const auto surface =
      ((g.node_class == kWaterSurface) | (g.node_class == kOilSurface)).to(torch::kFloat32);
  const auto link = torch::one_hot(g.link_type, kLinkTypes).to(torch::kFloat32);
  return torch::cat({g.edge_features, difference(velocity), difference(material),
                     surface.index_select(0, receivers).unsqueeze(1),
                     surface.index_select(0, senders).unsqueeze(1), link},
                    1);
}

PhysicsModuleImpl::PhysicsModuleImpl(int64_t width, int64_t heads) {
  encoder_ = register_module("encoder", Mlp(kRelationFeatures, width, width, 1, false));
  heads_ = register_module("heads", torch::nn::Linear(width, heads));
}

torch::Tensor PhysicsModuleImpl::forward(const torch::Tensor& relations) {
  return heads_->forward(torch::relu(encoder_->forward(relations)));
}

double PhysicsModuleImpl::flops_per_edge() const {
  return encoder_->flops_per_row() + 2.0 * double(heads_->weight.numel());
}

}  // namespace gnn
