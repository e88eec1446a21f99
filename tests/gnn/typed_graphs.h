#pragma once
// Hand-made typed graphs for PAGATNet's tests.
#include <torch/torch.h>

#include "gnn/data/dataset.h"
#include "gnn/graph/heterogeneous_typing.h"
#include "gnn/graph/radius_graph.h"

namespace typed_graphs {

// n nodes in the unit cube, typed: boundary below z = 0.12, oil at x > 0.5, water elsewhere
// (phases apart, so that some nodes are more than two hops from the other phase), with a kernel
// volume of one node's share of the cube (a full neighbourhood sums to about 1).
inline gnn::GraphInput random_typed_graph(int64_t n, double radius) {
  auto points = torch::rand({n, 3});
  auto x = points.select(1, 0), z = points.select(1, 2);
  auto type = torch::where(x > 0.5, torch::full({n}, gnn::kOil, torch::kInt64),
                           torch::full({n}, gnn::kWater, torch::kInt64));
  type = torch::where(z < 0.12, torch::full({n}, gnn::kBoundary, torch::kInt64), type);
  auto graph = gnn::build_radius_graph(points, torch::zeros({0, 3}), radius);
  auto typing = gnn::type_graph(points, type, graph.edge_index, radius, 1.0 / double(n),
                                gnn::SurfaceRule::kernel_sum(0.92));
  gnn::GraphInput g;
  g.node_features = torch::randn({n, gnn::kNodeFeatures});
  g.node_type = type;
  g.edge_index = graph.edge_index;
  g.edge_features = torch::randn({graph.edge_index.size(1), gnn::kEdgeFeatures});
  g.fluid = type != gnn::kBoundary;
  g.node_class = typing.node_class;
  g.link_type = typing.link_type;
  return g;
}

}  // namespace typed_graphs
