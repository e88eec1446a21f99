#include "gnn/graph/heterogeneous_typing.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "gnn/data/dataset.h"
#include "gnn/graph/graph_input.h"
#include "sph/core/kernels.h"

namespace gnn {

namespace {

// The edges and nodes the typing reads, as raw arrays (the tensors kept alive by the caller).
struct TypingInput {
  int64_t n = 0, E = 0;
  const float* x = nullptr;
  const int64_t *type = nullptr, *senders = nullptr, *receivers = nullptr;
};

// Refuses node types outside the contract's, edges naming nodes that are not there, and edges
// not sorted by receiver.
void check_typing_input(const TypingInput& in, const std::string& where) {
  for (int64_t i = 0; i < in.n; ++i)
    if (in.type[i] < kWater || in.type[i] > kBoundary)
      throw std::invalid_argument(where + ": node " + std::to_string(i) + " has type " +
                                  std::to_string(in.type[i]) + " (0 water, 1 oil, 2 boundary)");
  for (int64_t k = 0; k < in.E; ++k) {
    const int64_t j = in.senders[k], i = in.receivers[k];
    if (j < 0 || j >= in.n || i < 0 || i >= in.n)
      throw std::invalid_argument(where + ": edge " + std::to_string(k) +
                                  " names a node outside 0.." + std::to_string(in.n - 1));
    if (k > 0 && i < in.receivers[k - 1])
      throw std::invalid_argument(where + ": the edges are not sorted by receiver (edge " +
                                  std::to_string(k) + ")");
  }
}

// Kernel sums and neighbour centroids over the same phase (and the boundary), and which fluid
// nodes lie in the interface band: the other fluid phase within two hops.
struct PhaseNeighbourhood {
  torch::Tensor kernel_sum, centroid_offset;  // [n] each
  std::vector<char> interface_band;
};

PhaseNeighbourhood phase_neighbourhood(const TypingInput& in, double radius,
                                       double particle_volume) {
  const int64_t n = in.n;
  const float* x = in.x;
  const int64_t* type = in.type;
  const sph::CubicSplineKernel kernel{sph::Real(radius)};
  const float self = float(kernel.value(sph::Real(0)) * particle_volume);
  PhaseNeighbourhood out;
  out.kernel_sum = torch::zeros({n});
  float* sum = out.kernel_sum.data_ptr<float>();
  std::vector<double> offset_sum(size_t(3 * n), 0.0);
  std::vector<int64_t> same_phase_neighbours(size_t(n), 0);
  std::vector<char> other_phase_near(size_t(n), 0);
  for (int64_t i = 0; i < n; ++i)
    if (type[i] != kBoundary) sum[i] = self;
  for (int64_t k = 0; k < in.E; ++k) {
    const int64_t i = in.receivers[k], j = in.senders[k];
    if (type[i] == kBoundary) continue;
    if (type[j] == kBoundary || type[j] == type[i]) {
      const float dx = x[3 * j] - x[3 * i], dy = x[3 * j + 1] - x[3 * i + 1],
                  dz = x[3 * j + 2] - x[3 * i + 2];
      sum[i] +=
          float(kernel.value(sph::Real(std::sqrt(dx * dx + dy * dy + dz * dz))) * particle_volume);
      offset_sum[size_t(3 * i)] += dx;
      offset_sum[size_t(3 * i + 1)] += dy;
      offset_sum[size_t(3 * i + 2)] += dz;
      ++same_phase_neighbours[size_t(i)];
    } else {
      other_phase_near[size_t(i)] = 1;  // a fluid neighbour of the other phase: one hop
    }
  }
  const double diameter = std::cbrt(particle_volume);
  out.centroid_offset = torch::zeros({n});
  float* offset = out.centroid_offset.data_ptr<float>();
  for (int64_t i = 0; i < n; ++i) {
    if (type[i] == kBoundary) continue;
    const auto count = double(same_phase_neighbours[size_t(i)]);
    if (count == 0) {
      offset[i] = float(radius / diameter);
      continue;
    }
    const double* o = &offset_sum[size_t(3 * i)];
    offset[i] = float(std::sqrt(o[0] * o[0] + o[1] * o[1] + o[2] * o[2]) / count / diameter);
  }
  // Two hops: a neighbour with the other phase one hop from it.
  out.interface_band = other_phase_near;
  for (int64_t k = 0; k < in.E; ++k) {
    const int64_t i = in.receivers[k], j = in.senders[k];
    if (type[i] != kBoundary && type[j] != kBoundary && other_phase_near[size_t(j)])
      out.interface_band[size_t(i)] = 1;
  }
  return out;
}

}  // namespace

HeterogeneousTyping type_graph(const torch::Tensor& position_in, const torch::Tensor& node_type_in,
                               const torch::Tensor& edge_index_in, double radius,
                               double particle_volume, SurfaceRule rule) {
  const std::string where = "heterogeneous typing";
  check_tensor(where, "position", position_in, {-1, 3}, torch::kFloat32, torch::kCPU, false);
  const int64_t n = position_in.size(0);
  check_tensor(where, "node_type", node_type_in, {n}, torch::kInt64, torch::kCPU, false);
  check_tensor(where, "edge_index", edge_index_in, {2, -1}, torch::kInt64, torch::kCPU, false);
  const auto position = position_in.contiguous();
  const auto node_type = node_type_in.contiguous();
  const auto edge_index = edge_index_in.contiguous();
  TypingInput in;
  in.n = n;
  in.E = edge_index.size(1);
  in.x = position.data_ptr<float>();
  in.type = node_type.data_ptr<int64_t>();
  in.senders = edge_index.data_ptr<int64_t>();
  in.receivers = in.senders + in.E;
  check_typing_input(in, where);
  const PhaseNeighbourhood near = phase_neighbourhood(in, radius, particle_volume);
  const int64_t* type = in.type;
  const float* sum = near.kernel_sum.data_ptr<float>();
  const float* offset = near.centroid_offset.data_ptr<float>();

  HeterogeneousTyping out;
  out.kernel_sum = near.kernel_sum;
  out.centroid_offset = near.centroid_offset;
  out.node_class = torch::empty({n}, torch::kInt64);
  int64_t* node_class = out.node_class.data_ptr<int64_t>();
  std::vector<char> surface(size_t(n), 0);
  for (int64_t i = 0; i < n; ++i) {
    if (type[i] == kBoundary) {
      node_class[i] = kBoundaryClass;
      continue;
    }
    const bool by_rule = rule.kind == SurfaceRule::Kind::kKernelSum
                             ? sum[i] < float(rule.threshold)
                             : offset[i] > float(rule.threshold);
    surface[size_t(i)] = by_rule || near.interface_band[size_t(i)];
    node_class[i] = (type[i] == kOil ? kOilInner : kWaterInner) + surface[size_t(i)];
  }
  out.link_type = torch::empty({in.E}, torch::kInt64);
  int64_t* link = out.link_type.data_ptr<int64_t>();
  for (int64_t k = 0; k < in.E; ++k) {
    const int64_t i = in.receivers[k], j = in.senders[k];
    if (type[i] == kBoundary || type[j] == kBoundary)
      link[k] = kLinkBD;
    else if (type[i] != type[j])
      link[k] = kLinkDP;
    else if (surface[size_t(i)] && surface[size_t(j)])
      link[k] = kLinkST;
    else
      link[k] = kLinkSP;
  }
  return out;
}

std::array<TypedEdges, kLinkTypes> edges_by_link_type(const torch::Tensor& link_type_in,
                                                      const torch::Tensor& receivers_in,
                                                      int64_t nodes) {
  const auto link_type = link_type_in.contiguous();
  const auto receivers = receivers_in.contiguous();
  const int64_t E = link_type.size(0);
  if (receivers.size(0) != E)
    throw std::invalid_argument("edges by link type: " + std::to_string(E) + " link types for " +
                                std::to_string(receivers.size(0)) + " receivers");
  const int64_t* link = link_type.data_ptr<int64_t>();
  const int64_t* receiver = receivers.data_ptr<int64_t>();
  std::array<std::vector<int64_t>, kLinkTypes> edges;
  std::array<std::vector<int64_t>, kLinkTypes> counts;
  for (auto& c : counts) c.assign(size_t(nodes) + 1, 0);
  for (int64_t k = 0; k < E; ++k) {
    if (link[k] < 0 || link[k] >= kLinkTypes)
      throw std::invalid_argument("edges by link type: edge " + std::to_string(k) +
                                  " has link type " + std::to_string(link[k]));
    edges[size_t(link[k])].push_back(k);
    ++counts[size_t(link[k])][size_t(receiver[k]) + 1];
  }
  std::array<TypedEdges, kLinkTypes> out;
  for (size_t t = 0; t < size_t(kLinkTypes); ++t) {
    for (size_t i = 1; i < counts[t].size(); ++i) counts[t][i] += counts[t][i - 1];
    out[t].edges = torch::tensor(edges[t], torch::kInt64);
    out[t].offsets = torch::tensor(counts[t], torch::kInt64);
  }
  return out;
}

}  // namespace gnn
