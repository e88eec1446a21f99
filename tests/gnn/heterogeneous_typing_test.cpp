// PAGATNet's heterogeneous typing (gnn/graph/heterogeneous_typing.h) on hand-made lattices of
// spacing d with a connectivity radius just under 2 d (lattice pairs at exactly 2 d would be
// ties that float rounding decides). On such a lattice the cubic spline's kernel sum of a full
// neighbourhood is 1.00, of a particle with its upper half-space empty 0.85 (its neighbours above:
// one at d, four at sqrt(2) d and four at sqrt(3) d), so gamma = 0.92 splits them.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <tuple>

#include "gnn/data/dataset.h"
#include "gnn/graph/heterogeneous_typing.h"
#include "gnn/graph/radius_graph.h"
#include "gnn/graph/segment_ops.h"

namespace {

constexpr double kSpacing = 0.02;
constexpr double kRadius = 2 * kSpacing * (1 - 1e-4);
constexpr double kVolume = kSpacing * kSpacing * kSpacing;
constexpr double kGamma = 0.92;

// Lattice points k * d for integer k in [lo, hi] on every axis (hi inclusive).
torch::Tensor lattice(std::array<int, 3> lo, std::array<int, 3> hi) {
  std::vector<float> p;
  for (int i = lo[0]; i <= hi[0]; ++i)
    for (int j = lo[1]; j <= hi[1]; ++j)
      for (int k = lo[2]; k <= hi[2]; ++k)
        for (int c : {i, j, k}) p.push_back(float(c * kSpacing));
  return torch::tensor(p).view({-1, 3});
}

struct Typed {
  torch::Tensor position, node_type, edge_index;
  gnn::HeterogeneousTyping typing;
};

// The radius graph of `fluid` with `boundary` and the typing of its nodes.
Typed type_lattice(const torch::Tensor& fluid, const torch::Tensor& fluid_type,
                   const torch::Tensor& boundary) {
  Typed t;
  auto graph = gnn::build_radius_graph(fluid, boundary, kRadius);
  const int64_t kept = graph.boundary_nodes.size(0);
  t.position = torch::cat({fluid, boundary.index_select(0, graph.boundary_nodes)});
  t.node_type = torch::cat({fluid_type, torch::full({kept}, gnn::kBoundary, torch::kInt64)});
  t.edge_index = graph.edge_index;
  t.typing = gnn::type_graph(t.position, t.node_type, t.edge_index, kRadius, kVolume,
                             gnn::SurfaceRule::kernel_sum(kGamma));
  return t;
}

// Integer lattice coordinates of node i.
std::array<int, 3> cell_of(const torch::Tensor& position, int64_t i) {
  auto p = position[i];
  return {int(std::lround(p[0].item<float>() / kSpacing)),
          int(std::lround(p[1].item<float>() / kSpacing)),
          int(std::lround(p[2].item<float>() / kSpacing))};
}

}  // namespace

// A flat water layer 10 x 10 x 5 on a boundary floor: the top layer is surface, every other
// particle of the central 4 x 4 columns (away from the sides, which are free surfaces too) is
// inner, the bottom one included (the floor counts in its kernel sum); the kernel sums are those
// of the header; links to the floor are BD and the floor's nodes are boundary.
TEST(HeterogeneousTyping, AFlatWaterLayerIsSurfaceOnTopAndInnerBelow) {
  auto water = lattice({0, 0, 0}, {9, 9, 4});
  auto floor = lattice({-2, -2, -2}, {11, 11, -1});
  auto t = type_lattice(water, torch::zeros({water.size(0)}, torch::kInt64), floor);
  const auto& cls = t.typing.node_class;
  int checked_top = 0, checked_below = 0;
  for (int64_t i = 0; i < water.size(0); ++i) {
    const auto c = cell_of(t.position, i);
    if (c[0] < 3 || c[0] > 6 || c[1] < 3 || c[1] > 6) continue;  // central columns only
    const float sum = t.typing.kernel_sum[i].item<float>();
    if (c[2] == 4) {
      EXPECT_EQ(cls[i].item<int64_t>(), gnn::kWaterSurface) << "top node " << i;
      EXPECT_NEAR(sum, 0.85, 0.01);
      ++checked_top;
    } else {
      EXPECT_EQ(cls[i].item<int64_t>(), gnn::kWaterInner) << "node " << i << " at z " << c[2];
      EXPECT_NEAR(sum, 1.0, 0.01);
      ++checked_below;
    }
  }
  EXPECT_EQ(checked_top, 16);
  EXPECT_EQ(checked_below, 64);
  // Every boundary node is of the boundary class, and a link is BD exactly when it has a
  // boundary end; the bottom layer has some.
  const int64_t F = water.size(0);
  EXPECT_TRUE((cls.slice(0, F) == gnn::kBoundaryClass).all().item<bool>());
  auto has_boundary_end = (t.edge_index[0] >= F) | (t.edge_index[1] >= F);
  EXPECT_TRUE(torch::equal(t.typing.link_type == gnn::kLinkBD, has_boundary_end));
  EXPECT_GT(has_boundary_end.sum().item<int64_t>(), 0);
  EXPECT_EQ((t.typing.link_type == gnn::kLinkDP).sum().item<int64_t>(), 0);
}

// The neighbour-centroid rule at the 1.5 d the river models use, on the same layer: a node's
// neighbours are then the lattice points at d and sqrt(2) d (sqrt(3) d = 1.73 d is out). A top
// node has 13 (4 + 4 beside it, 1 + 4 below), 5 of them one d lower and the rest level, so their
// mean is 5/13 d = 0.385 d below it; a node with all 18 has its mean on itself. Threshold 0.25 d
// types the top surface and everything below inner (the floor counts as the same phase).
TEST(HeterogeneousTyping, TheNeighbourCentroidTypesAFlatLayerAtOneAndAHalfDiameters) {
  const double radius = 1.5 * kSpacing;
  auto water = lattice({0, 0, 0}, {9, 9, 4});
  auto floor = lattice({-2, -2, -2}, {11, 11, -1});
  auto graph = gnn::build_radius_graph(water, floor, radius);
  const int64_t F = water.size(0);
  auto position = torch::cat({water, floor.index_select(0, graph.boundary_nodes)});
  auto type =
      torch::cat({torch::zeros({F}, torch::kInt64),
                  torch::full({graph.boundary_nodes.size(0)}, gnn::kBoundary, torch::kInt64)});
  const auto typing = gnn::type_graph(position, type, graph.edge_index, radius, kVolume,
                                      gnn::SurfaceRule::neighbour_centroid(0.25));
  int checked_top = 0, checked_below = 0;
  for (int64_t i = 0; i < F; ++i) {
    const auto c = cell_of(position, i);
    if (c[0] < 3 || c[0] > 6 || c[1] < 3 || c[1] > 6) continue;  // central columns only
    const float offset = typing.centroid_offset[i].item<float>();
    if (c[2] == 4) {
      EXPECT_NEAR(offset, 5.0 / 13.0, 1e-4) << "top node " << i;
      EXPECT_EQ(typing.node_class[i].item<int64_t>(), gnn::kWaterSurface);
      ++checked_top;
    } else {
      EXPECT_NEAR(offset, 0.0, 1e-4) << "node " << i << " at z " << c[2];
      EXPECT_EQ(typing.node_class[i].item<int64_t>(), gnn::kWaterInner);
      ++checked_below;
    }
  }
  EXPECT_EQ(checked_top, 16);
  EXPECT_EQ(checked_below, 64);
  // A lone particle has no neighbour to average: it is surface.
  auto lone = gnn::type_graph(torch::zeros({1, 3}), torch::zeros({1}, torch::kInt64),
                              torch::zeros({2, 0}, torch::kInt64), radius, kVolume,
                              gnn::SurfaceRule::neighbour_centroid(0.25));
  EXPECT_EQ(lone.node_class[0].item<int64_t>(), gnn::kWaterSurface);
}

// A 5 x 5 x 5 oil droplet in the middle of a 13 x 13 x 13 block of water: the droplet's rim is
// surface and only its centre (whose two-hop neighbourhood is all oil) inner; water one or two
// lattice shells out is within two hops of the oil and surface, the third shell inner (a hop is
// shorter than 2 d, so two hops cannot cross three shells), and the block's outer face surface; DP
// links are exactly the oil-water pairs, and ST and SP split the rest by the surface flags.
TEST(HeterogeneousTyping, AnOilDropletHasASurfaceRimAndDpLinksOnlyAcrossTheInterface) {
  auto fluid = lattice({-6, -6, -6}, {6, 6, 6});
  const int64_t n = fluid.size(0);
  auto type = torch::zeros({n}, torch::kInt64);
  for (int64_t i = 0; i < n; ++i) {
    const auto c = cell_of(fluid, i);
    if (std::abs(c[0]) <= 2 && std::abs(c[1]) <= 2 && std::abs(c[2]) <= 2) type[i] = gnn::kOil;
  }
  auto t = type_lattice(fluid, type, torch::zeros({0, 3}));
  const auto& cls = t.typing.node_class;
  for (int64_t i = 0; i < n; ++i) {
    const auto c = cell_of(fluid, i);
    const int far = std::max({std::abs(c[0]), std::abs(c[1]), std::abs(c[2])});
    const int64_t got = cls[i].item<int64_t>();
    if (far == 0) {
      EXPECT_EQ(got, gnn::kOilInner) << "the droplet's centre";
    } else if (far <= 2) {
      EXPECT_EQ(got, gnn::kOilSurface) << "oil at " << c[0] << " " << c[1] << " " << c[2];
    } else if (far <= 4) {
      // Within two hops of the oil: the oil particle nearest to it (each coordinate clamped to
      // the droplet) is at most sqrt(3) d away from a node of this shell or the one inside it.
      EXPECT_EQ(got, gnn::kWaterSurface) << "water at " << c[0] << " " << c[1] << " " << c[2];
    } else if (far == 5) {
      EXPECT_EQ(got, gnn::kWaterInner) << "water at " << c[0] << " " << c[1] << " " << c[2];
    } else {
      EXPECT_EQ(got, gnn::kWaterSurface) << "the block's outer face";
    }
  }
  const auto sender_type = type.index_select(0, t.edge_index[0]);
  const auto receiver_type = type.index_select(0, t.edge_index[1]);
  const auto& link = t.typing.link_type;
  EXPECT_TRUE(torch::equal(link == gnn::kLinkDP, sender_type != receiver_type));
  EXPECT_GT((link == gnn::kLinkDP).sum().item<int64_t>(), 0);
  const auto surface = (cls == gnn::kWaterSurface) | (cls == gnn::kOilSurface);
  const auto both_surface =
      surface.index_select(0, t.edge_index[0]) & surface.index_select(0, t.edge_index[1]);
  const auto same = sender_type == receiver_type;
  EXPECT_TRUE(torch::equal(link == gnn::kLinkST, same & both_surface));
  EXPECT_TRUE(torch::equal(link == gnn::kLinkSP, same & ~both_surface));
  EXPECT_GT((link == gnn::kLinkSP).sum().item<int64_t>(), 0);
  EXPECT_GT((link == gnn::kLinkST).sum().item<int64_t>(), 0);
}

// Water with no boundary and no oil: DP and BD have no edges (empty lists, all-zero offsets);
// the per-type CSR lists hold every edge exactly once, each receiver's edges of a type in the
// full list's order and with that receiver and type.
TEST(HeterogeneousTyping, ATypeWithNoEdgesHasAnEmptyCsrAndTheTypesPartitionTheEdges) {
  auto water = lattice({0, 0, 0}, {5, 5, 5});
  const int64_t n = water.size(0);
  auto t = type_lattice(water, torch::zeros({n}, torch::kInt64), torch::zeros({0, 3}));
  auto by_type = gnn::edges_by_link_type(t.typing.link_type, t.edge_index[1], n);
  for (int64_t type : {gnn::kLinkDP, gnn::kLinkBD}) {
    EXPECT_EQ(by_type[size_t(type)].edges.numel(), 0);
    EXPECT_EQ(by_type[size_t(type)].offsets.size(0), n + 1);
    EXPECT_EQ(by_type[size_t(type)].offsets.abs().sum().item<int64_t>(), 0);
  }
  std::set<int64_t> seen;
  const auto receivers = t.edge_index[1];
  for (int64_t type = 0; type < gnn::kLinkTypes; ++type) {
    const auto& csr = by_type[size_t(type)];
    ASSERT_EQ(csr.offsets[n].item<int64_t>(), csr.edges.numel());
    for (int64_t i = 0; i < n; ++i) {
      int64_t previous = -1;
      for (int64_t k = csr.offsets[i].item<int64_t>(); k < csr.offsets[i + 1].item<int64_t>();
           ++k) {
        const int64_t e = csr.edges[k].item<int64_t>();
        EXPECT_EQ(receivers[e].item<int64_t>(), i);
        EXPECT_EQ(t.typing.link_type[e].item<int64_t>(), type);
        EXPECT_GT(e, previous);
        previous = e;
        EXPECT_TRUE(seen.insert(e).second) << "edge " << e << " twice";
      }
    }
  }
  EXPECT_EQ(int64_t(seen.size()), t.edge_index.size(1));
}

// The segment softmax over one link type's edges (PAGATNet's attention per type) against
// torch::softmax on each receiver's rows, values and gradients (float32, 1e-6 and 1e-5), on the
// SP edges around a 3 x 3 x 3 oil droplet in a 13^3 block of water (many receivers; the
// droplet's nodes, all surface, have none of that type); each receiver's weights sum to 1.
TEST(HeterogeneousTyping, SegmentSoftmaxPerLinkTypeEqualsASoftmaxPerReceiver) {
  torch::manual_seed(5);
  auto fluid = lattice({-6, -6, -6}, {6, 6, 6});
  const int64_t n = fluid.size(0);
  auto type = torch::zeros({n}, torch::kInt64);
  for (int64_t i = 0; i < n; ++i) {
    const auto c = cell_of(fluid, i);
    if (std::max({std::abs(c[0]), std::abs(c[1]), std::abs(c[2])}) <= 1) type[i] = gnn::kOil;
  }
  auto t = type_lattice(fluid, type, torch::zeros({0, 3}));
  const auto typed = gnn::edges_by_link_type(t.typing.link_type, t.edge_index[1], n);
  const auto& sp = typed[size_t(gnn::kLinkSP)];
  const auto receivers = t.edge_index[1].index_select(0, sp.edges);
  ASSERT_GT(sp.edges.numel(), 1000);
  auto scores = (3 * torch::randn({sp.edges.numel(), 3})).requires_grad_(true);
  auto weights = torch::randn({sp.edges.numel(), 3});
  auto alpha = gnn::segment_softmax(scores, receivers, sp.offsets);
  auto grad = torch::autograd::grad({(alpha * weights).sum()}, {scores})[0];

  auto reference_scores = scores.detach().clone().requires_grad_(true);
  std::vector<torch::Tensor> pieces;
  int empty = 0;
  for (int64_t i = 0; i < n; ++i) {
    const int64_t a = sp.offsets[i].item<int64_t>(), b = sp.offsets[i + 1].item<int64_t>();
    if (a == b) {
      ++empty;
      continue;
    }
    pieces.push_back(torch::softmax(reference_scores.slice(0, a, b), 0));
  }
  EXPECT_GT(empty, 0);  // the droplet (all surface, linked by ST and DP) has no SP edges
  auto reference = torch::cat(pieces);
  auto reference_grad = torch::autograd::grad({(reference * weights).sum()}, {reference_scores})[0];
  EXPECT_TRUE(torch::allclose(alpha, reference, 1e-5, 1e-6))
      << (alpha - reference).abs().max().item<float>();
  EXPECT_TRUE(torch::allclose(grad, reference_grad, 1e-4, 1e-5))
      << (grad - reference_grad).abs().max().item<float>();
  auto per_receiver = torch::zeros({n, 3}).index_add_(0, receivers, alpha.detach());
  auto has_edges = (sp.offsets.slice(0, 1) > sp.offsets.slice(0, 0, n));
  EXPECT_TRUE(torch::allclose(per_receiver.index({has_edges}), torch::ones({1}), 1e-5, 1e-5));
}

TEST(HeterogeneousTyping, BadInputIsAClearError) {
  auto water = lattice({0, 0, 0}, {2, 2, 2});
  const int64_t n = water.size(0);
  auto graph = gnn::build_radius_graph(water, torch::zeros({0, 3}), kRadius);
  auto type = torch::zeros({n}, torch::kInt64);
  auto message = [&](const torch::Tensor& p, const torch::Tensor& ty, const torch::Tensor& e) {
    try {
      gnn::type_graph(p, ty, e, kRadius, kVolume, gnn::SurfaceRule::kernel_sum(kGamma));
    } catch (const std::invalid_argument& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(water, type, graph.edge_index.flip(1)).find("not sorted by receiver"),
            std::string::npos);
  EXPECT_NE(message(water, type + 3, graph.edge_index).find("has type 3"), std::string::npos);
  EXPECT_NE(message(water, type.slice(0, 1), graph.edge_index).find("node_type"),
            std::string::npos);
}
