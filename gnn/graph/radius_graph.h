#pragma once
// The graph of one frame: every ordered pair of nodes closer than the connectivity radius, found
// on the simulator's uniform grid (sph::NeighbourGrid), never by comparing all pairs. Nodes are
// the fluid particles followed by the boundary particles within the radius of some fluid
// particle; boundary-boundary pairs are left out, since both ends are fixed and the pair tells
// the fluid nothing the boundary's fluid neighbours do not.

#include <torch/torch.h>

namespace gnn {

struct RadiusGraph {
  torch::Tensor boundary_nodes;  // [B] int64: indices into the boundary set, in node order
  torch::Tensor edge_index;      // [2, E] int64: row 0 senders, row 1 receivers (sorted)
};

// `fluid` [F, 3] and `boundary` [M, 3] float32 positions; node k < F is fluid particle k and node
// F + b is boundary particle boundary_nodes[b].
RadiusGraph build_radius_graph(const torch::Tensor& fluid, const torch::Tensor& boundary,
                               double radius);

// The same graph by comparing every pair: the reference the grid version is tested against.
RadiusGraph brute_force_radius_graph(const torch::Tensor& fluid, const torch::Tensor& boundary,
                                     double radius);

}  // namespace gnn
