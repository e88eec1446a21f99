#pragma once
// What a learned simulator sees of one frame (or a batch of frames joined as one graph):
// node features, node types, edges and edge features. Built by LearnedSimulator::encode from a
// window of positions; every model (GNS, DPI-Nets, PAGATNet) takes the same input.

#include <torch/torch.h>

#include <vector>

namespace gnn {

struct GraphInput {
  torch::Tensor node_features;  // [n, 23] float32: 5 velocities, 2 material, 6 bound distances
  torch::Tensor node_type;      // [n] int64: water, oil, boundary
  torch::Tensor edge_index;     // [2, E] int64: senders, receivers
  torch::Tensor edge_features;  // [E, 4] float32: (x_sender - x_receiver) / radius, its norm
  torch::Tensor fluid;          // [n] bool: the nodes whose acceleration is predicted
  int64_t nodes() const { return node_type.size(0); }
  int64_t edges() const { return edge_index.size(1); }
};

constexpr int64_t kVelocityFeatures = 15;
constexpr int64_t kMaterialFeatures = 2;
constexpr int64_t kBoundFeatures = 6;
constexpr int64_t kNodeFeatures = kVelocityFeatures + kMaterialFeatures + kBoundFeatures;
constexpr int64_t kEdgeFeatures = 4;

// Joins graphs into one with disjoint node sets (edge indices offset), for batches.
inline GraphInput join_graphs(const std::vector<GraphInput>& graphs) {
  if (graphs.size() == 1) return graphs[0];
  std::vector<torch::Tensor> nf, nt, ei, ef, fl;
  int64_t offset = 0;
  for (const auto& g : graphs) {
    nf.push_back(g.node_features);
    nt.push_back(g.node_type);
    ei.push_back(g.edge_index + offset);
    ef.push_back(g.edge_features);
    fl.push_back(g.fluid);
    offset += g.nodes();
  }
  return {torch::cat(nf), torch::cat(nt), torch::cat(ei, 1), torch::cat(ef), torch::cat(fl)};
}

}  // namespace gnn
