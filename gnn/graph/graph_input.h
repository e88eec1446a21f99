#pragma once
// What a learned simulator sees of one frame (or a batch of frames joined as one graph):
// node features, node types, edges and edge features. Built by LearnedSimulator::encode from a
// window of positions; every model (GNS, DPI-Nets, PAGATNet) takes the same input.

#include <torch/torch.h>

#include <string>
#include <vector>

namespace gnn {

struct GraphInput {
  // [n, 24] float32: 5 velocities, 2 material, the oil fraction, 6 bound distances
  torch::Tensor node_features;
  torch::Tensor node_type;      // [n] int64: water, oil (oil fraction >= 1/2), boundary
  torch::Tensor edge_index;     // [2, E] int64: senders, receivers
  torch::Tensor edge_features;  // [E, 4] float32: (x_sender - x_receiver) / radius, its norm
  torch::Tensor fluid;          // [n] bool: the nodes whose acceleration is predicted
  // Heterogeneous typing (PAGATNet, docs/models.md): built only for a model whose needs_typing()
  // says so, undefined otherwise.
  torch::Tensor node_class;  // [n] int64: oil/water x surface/inner, boundary
  torch::Tensor link_type;   // [E] int64: ST, SP, DP, BD
  int64_t nodes() const { return node_type.size(0); }
  int64_t edges() const { return edge_index.size(1); }
};

constexpr int64_t kVelocityFeatures = 15;
constexpr int64_t kMaterialFeatures = 2;
constexpr int64_t kFractionFeatures = 1;
constexpr int64_t kBoundFeatures = 6;
constexpr int64_t kNodeFeatures =
    kVelocityFeatures + kMaterialFeatures + kFractionFeatures + kBoundFeatures;
// The oil fraction's column (0 for boundary nodes).
constexpr int64_t kOilFractionColumn = kVelocityFeatures + kMaterialFeatures;
// node_features begins with the 5 velocities, oldest first, 3 columns each (x, y, z); the newest
// (x_t - x_(t-1), normalised) is columns kLastVelocityColumn .. kLastVelocityColumn + 2.
constexpr int64_t kLastVelocityColumn = kVelocityFeatures - 3;
constexpr int64_t kEdgeFeatures = 4;

// Throws std::invalid_argument "WHERE: NAME: ..." when `t` is missing or its sizes (-1: any
// extent), dtype, device or (with `contiguous`) layout differ, printing what it got.
void check_tensor(const std::string& where, const std::string& name, const torch::Tensor& t,
                  const std::vector<int64_t>& sizes, torch::ScalarType dtype,
                  const torch::Device& device, bool contiguous = true);

// Checks every tensor's shape, dtype, contiguity and device at a model's entry; a mismatch throws
// std::invalid_argument naming `where`, the tensor and the sizes it got.
void check_graph_input(const GraphInput& g, const std::string& where);

// The same graph with every tensor on `device`.
GraphInput to_device(const GraphInput& g, const torch::Device& device);

// Joins graphs into one with disjoint node sets (edge indices offset), for batches.
inline GraphInput join_graphs(const std::vector<GraphInput>& graphs) {
  if (graphs.size() == 1) return graphs[0];
  std::vector<torch::Tensor> nf, nt, ei, ef, fl, nc, lt;
  int64_t offset = 0;
  for (const auto& g : graphs) {
    nf.push_back(g.node_features);
    nt.push_back(g.node_type);
    ei.push_back(g.edge_index + offset);
    ef.push_back(g.edge_features);
    fl.push_back(g.fluid);
    if (g.node_class.defined()) nc.push_back(g.node_class);
    if (g.link_type.defined()) lt.push_back(g.link_type);
    offset += g.nodes();
  }
  GraphInput out;
  out.node_features = torch::cat(nf);
  out.node_type = torch::cat(nt);
  out.edge_index = torch::cat(ei, 1);
  out.edge_features = torch::cat(ef);
  out.fluid = torch::cat(fl);
  if (nc.size() == graphs.size()) out.node_class = torch::cat(nc);
  if (lt.size() == graphs.size()) out.link_type = torch::cat(lt);
  return out;
}

}  // namespace gnn
