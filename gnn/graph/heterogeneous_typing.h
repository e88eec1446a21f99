#pragma once
// PAGATNet's heterogeneous graph (docs/models.md, "Heterogeneous graph"): each node's class and
// the type of every link of a frame's radius graph, recomputed each frame from the current
// positions and phases.
//
// Nodes. Boundary nodes are their own class. A fluid node is water or oil by its phase (the oil
// fraction >= 1/2, gnn::phase_from_fraction) and surface or inner:
//  - surface when its kernel sum  sum_j W(|x_i - x_j|) V  over itself and its neighbours of the
//    same phase falls below gamma (a full neighbourhood gives about 1), or
//  - when a node of the other fluid phase is at most two hops away (the interface's band).
// Our reading: boundary neighbours count in the kernel sum with the same phase. docs/models.md says
// "same-phase neighbours"; a wall is not a free surface, and without this every particle resting
// on the floor of a tank would be typed as surface, like those at the air.
// The kernel is the simulator's cubic spline with the graph's connectivity radius as its support,
// and V is the particles' rest volume (one diameter cubed, boundary particles included).
//
// Links. An edge between two fluid nodes is DP when their phases differ, else ST when both are
// surface, else SP (surface-inner or inner-inner); an edge to or from a boundary node is BD.
//
// Per link type the edges are also given in CSR form by receiver (the edge list is sorted by
// receiver, so each type's edges keep that order), for segment softmax and sums per type.

#include <torch/torch.h>

#include <array>

namespace gnn {

// Node classes (GraphInput::node_class): phase x surface/inner, and the boundary.
constexpr int64_t kWaterInner = 0, kWaterSurface = 1, kOilInner = 2, kOilSurface = 3,
                  kBoundaryClass = 4;
// The fluid classes a classification head predicts (PAGATNet's L_att): the first four.
constexpr int64_t kFluidNodeClasses = 4;
// Link types (GraphInput::link_type).
constexpr int64_t kLinkST = 0, kLinkSP = 1, kLinkDP = 2, kLinkBD = 3;
constexpr int64_t kLinkTypes = 4;

struct HeterogeneousTyping {
  torch::Tensor node_class;  // [n] int64, the classes above
  torch::Tensor link_type;   // [E] int64, the link types above
  torch::Tensor kernel_sum;  // [n] float32: the same-phase kernel sum (0 for boundary nodes)
};

// `position` [n, 3] float32 and `node_type` [n] int64 (kWater, kOil, kBoundary of
// gnn/data/dataset.h), `edge_index` [2, E] int64 sorted by receiver (build_radius_graph's order).
// Throws std::invalid_argument on other shapes, a node type outside the three or an unsorted
// edge list.
HeterogeneousTyping type_graph(const torch::Tensor& position, const torch::Tensor& node_type,
                               const torch::Tensor& edge_index, double radius,
                               double particle_volume, double gamma);

// The edges of one link type, by receiver: receiver i's edges of the type are
// edges[offsets[i] .. offsets[i + 1]), indices into the full edge list in its order.
struct TypedEdges {
  torch::Tensor edges;    // [E_T] int64
  torch::Tensor offsets;  // [n + 1] int64
};

// CSR per link type from `link_type` [E] and the receivers [E] (sorted) of an n-node graph.
// A type without edges has an empty edge list and all-zero offsets.
std::array<TypedEdges, kLinkTypes> edges_by_link_type(const torch::Tensor& link_type,
                                                      const torch::Tensor& receivers,
                                                      int64_t nodes);

}  // namespace gnn
