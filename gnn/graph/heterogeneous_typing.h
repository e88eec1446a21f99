#pragma once
// PAGATNet's heterogeneous graph (docs/models.md, "Heterogeneous graph"): each node's class and
// the type of every link of a frame's radius graph, recomputed each frame from the current
// positions and phases.
//
// Nodes. Boundary nodes are their own class. A fluid node is water or oil by its phase (the oil
// fraction >= 1/2, gnn::phase_from_fraction) and surface or inner: surface when a node of the
// other fluid phase is at most two hops away (the interface's band), or by one of two rules on
// its neighbours of the same phase (SurfaceRule):
//  - kernel sum (the paper's): its kernel sum  sum_j W(|x_i - x_j|) V  over itself and those
//    neighbours falls below gamma. The kernel is the simulator's cubic spline with the graph's
//    connectivity radius as its support, V the particles' rest volume (one diameter cubed).
//  - neighbour centroid (ours, the default): the mean of those neighbours' positions lies more
//    than `threshold` particle diameters from the node (a node without such neighbours: the
//    radius, the farthest a mean can be). At the 1.5 diameters our models use, the kernel sum of
//    a full lattice neighbourhood (1.09) and of a flat top layer (1.04) differ by less than the
//    disorder of real SPH frames, and no gamma types the free surface of river frames better than
//    typing everything; the centroid, whose top-layer offset is 0.38 diameters on a lattice, does
//    (docs/results/surface_typing.md).
// Our reading: boundary neighbours count with the same phase. docs/models.md says "same-phase
// neighbours"; a wall is not a free surface, and without this every particle resting on the floor
// of a tank would be typed as surface, like those at the air.
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

// How a fluid node outside the interface band is found to be at the surface.
struct SurfaceRule {
  enum class Kind { kNeighbourCentroid, kKernelSum };
  Kind kind = Kind::kNeighbourCentroid;
  double threshold = 0.26;  // centroid offset in diameters (above: surface), or gamma (below)
  static SurfaceRule neighbour_centroid(double diameters) {
    return {Kind::kNeighbourCentroid, diameters};
  }
  static SurfaceRule kernel_sum(double gamma) { return {Kind::kKernelSum, gamma}; }
};

struct HeterogeneousTyping {
  torch::Tensor node_class;  // [n] int64, the classes above
  torch::Tensor link_type;   // [E] int64, the link types above
  torch::Tensor kernel_sum;  // [n] float32: the same-phase kernel sum (0 for boundary nodes)
  // [n] float32: the same-phase neighbours' mean position's distance from the node, in particle
  // diameters (0 for boundary nodes)
  torch::Tensor centroid_offset;
};

// `position` [n, 3] float32 and `node_type` [n] int64 (kWater, kOil, kBoundary of
// gnn/data/dataset.h), `edge_index` [2, E] int64 sorted by receiver (build_radius_graph's order).
// `particle_volume` is one diameter cubed. Throws std::invalid_argument on other shapes, a node
// type outside the three or an unsorted edge list.
HeterogeneousTyping type_graph(const torch::Tensor& position, const torch::Tensor& node_type,
                               const torch::Tensor& edge_index, double radius,
                               double particle_volume, SurfaceRule rule);

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
