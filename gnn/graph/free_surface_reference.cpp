#include "gnn/graph/free_surface_reference.h"

#include <cmath>
#include <vector>

#include "gnn/data/dataset.h"
#include "gnn/graph/radius_graph.h"

namespace gnn {

torch::Tensor free_surface_by_cone(const torch::Tensor& fluid_in, double reach, double half_angle) {
  const auto fluid = fluid_in.contiguous();
  const int64_t n = fluid.size(0);
  const auto graph = build_radius_graph(fluid, torch::zeros({0, 3}), reach);
  const auto edges = graph.edge_index.contiguous();
  const int64_t E = edges.size(1);
  const int64_t* senders = edges.data_ptr<int64_t>();
  const int64_t* receivers = senders + E;
  const float* x = fluid.data_ptr<float>();
  const double cos_half_angle = std::cos(half_angle);
  std::vector<char> covered(size_t(n), 0);
  for (int64_t k = 0; k < E; ++k) {
    const int64_t i = receivers[k], j = senders[k];
    const double dx = x[3 * j] - x[3 * i], dy = x[3 * j + 1] - x[3 * i + 1],
                 dz = x[3 * j + 2] - x[3 * i + 2];
    const double distance = std::sqrt(dx * dx + dy * dy + dz * dz);
    if (distance > 0 && dz >= cos_half_angle * distance) covered[size_t(i)] = 1;
  }
  auto surface = torch::empty({n}, torch::kBool);
  bool* s = surface.data_ptr<bool>();
  for (int64_t i = 0; i < n; ++i) s[i] = !covered[size_t(i)];
  return surface;
}

FrameSurfaceTyping type_frame_surface(const torch::Tensor& fluid_in,
                                      const torch::Tensor& oil_fraction,
                                      const torch::Tensor& boundary, double radius, double diameter,
                                      double reach, double half_angle) {
  const auto fluid = fluid_in.contiguous();
  const int64_t F = fluid.size(0);
  const auto graph = build_radius_graph(fluid, boundary, radius);
  const auto kept_boundary = boundary.index_select(0, graph.boundary_nodes);
  const auto types =
      torch::cat({torch::where(oil_fraction >= 0.5, torch::full({F}, kOil, torch::kInt64),
                               torch::full({F}, kWater, torch::kInt64)),
                  torch::full({kept_boundary.size(0)}, kBoundary, torch::kInt64)});
  // A kernel-sum threshold of 0 types surface only the interface band.
  const auto typing =
      type_graph(torch::cat({fluid, kept_boundary}, 0), types, graph.edge_index, radius,
                 diameter * diameter * diameter, SurfaceRule::kernel_sum(0.0));
  const auto fluid_class = typing.node_class.slice(0, 0, F);
  const auto band = (fluid_class == kWaterSurface) | (fluid_class == kOilSurface);
  return {typing.kernel_sum.slice(0, 0, F), typing.centroid_offset.slice(0, 0, F),
          free_surface_by_cone(fluid, reach, half_angle), ~band};
}

torch::Tensor surface_by_rule(const SurfaceRule& rule, const FrameSurfaceTyping& frame) {
  return rule.kind == SurfaceRule::Kind::kKernelSum ? frame.kernel_sum < rule.threshold
                                                    : frame.centroid_offset > rule.threshold;
}

SurfaceAgreement surface_agreement(const torch::Tensor& typed, const torch::Tensor& reference,
                                   const torch::Tensor& counted) {
  const auto t = typed.index({counted}), r = reference.index({counted});
  SurfaceAgreement a;
  a.nodes = t.size(0);
  if (a.nodes == 0) return a;
  const double typed_count = double(t.sum().item<int64_t>());
  const double reference_count = double(r.sum().item<int64_t>());
  const double both = double((t & r).sum().item<int64_t>());
  a.typed_share = typed_count / double(a.nodes);
  a.reference_share = reference_count / double(a.nodes);
  a.precision = typed_count > 0 ? both / typed_count : 0;
  a.recall = reference_count > 0 ? both / reference_count : 0;
  a.f1 = a.precision + a.recall > 0 ? 2 * a.precision * a.recall / (a.precision + a.recall) : 0;
  return a;
}

}  // namespace gnn
