#include "gnn/models/learned_simulator.h"

#include "gnn/data/frame_window.h"
#include "gnn/graph/heterogeneous_typing.h"
#include "gnn/graph/radius_graph.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace gnn {

LearnedSimulator::LearnedSimulator(std::shared_ptr<GraphModel> model, Normalisation normalisation,
                                   Bounds bounds, double particle_radius)
    : model_(std::move(model)),
      normalisation_(std::move(normalisation)),
      bounds_(bounds),
      particle_radius_(particle_radius) {
  model_->set_normalisation(normalisation_);
}

void check_frame_nodes(const FrameNodes& f, const std::string& where) {
  // CPU tensors, any layout (windows are slices of the recorded trajectory).
  auto check = [&](const char* name, const torch::Tensor& t, std::vector<int64_t> sizes,
                   torch::ScalarType dtype) {
    check_tensor(where, std::string("frame ") + name, t, sizes, dtype, torch::kCPU,
                 /*contiguous=*/false);
  };
  check("history", f.history, {-1, kWindow, 3}, torch::kFloat32);
  const int64_t n = f.history.size(0);
  check("oil_fraction", f.oil_fraction, {n}, torch::kFloat32);
  check("material", f.material, {3, kMaterialFeatures}, torch::kFloat32);
  check("boundary", f.boundary, {-1, 3}, torch::kFloat32);
}

void LearnedSimulator::to(const torch::Device& device) {
  model_->to(device);
}

GraphInput LearnedSimulator::encode(const FrameNodes& f) const {
  check_frame_nodes(f, "LearnedSimulator::encode");
  const double radius = model_->radius();
  const int64_t fluid_count = f.history.size(0);
  auto current = f.history.select(1, kWindow - 1).contiguous();
  RadiusGraph graph = build_radius_graph(current, f.boundary, radius);
  const int64_t boundary_count = graph.boundary_nodes.size(0);
  auto boundary = f.boundary.index_select(0, graph.boundary_nodes);
  auto position = torch::cat({current, boundary});

  // Velocities of the window, normalised; boundary nodes stand still.
  auto velocity = f.history.slice(1, 1) - f.history.slice(1, 0, kWindow - 1);  // [n, 5, 3]
  velocity = torch::cat({velocity, torch::zeros({boundary_count, kWindow - 1, 3})});
  velocity = (velocity - normalisation_.vel_mean) / normalisation_.vel_std;

  // The phase by the oil fraction (spill.json's rule), and the material of the mixture: linear
  // in the fraction, as MTDF-SPH mixes rest density and viscosity.
  auto type = torch::cat({phase_from_fraction(f.oil_fraction),
                          torch::full({boundary_count}, kBoundary, torch::kInt64)});
  auto fraction = f.oil_fraction.unsqueeze(1);
  auto fluid_material =
      f.material[kWater].unsqueeze(0) + fraction * (f.material[kOil] - f.material[kWater]);
  auto material =
      torch::cat({fluid_material, f.material[kBoundary].unsqueeze(0).expand({boundary_count, -1})});
  fraction = torch::cat({fraction, torch::zeros({boundary_count, 1})});

  // Distances to the domain's faces in radii, clipped to [-1, 1]: a wall is felt only within
  // reach of the graph.
  auto lower = torch::tensor({float(bounds_[0][0]), float(bounds_[1][0]), float(bounds_[2][0])});
  auto upper = torch::tensor({float(bounds_[0][1]), float(bounds_[1][1]), float(bounds_[2][1])});
  auto bound_distance =
      torch::cat({position - lower, upper - position}, 1).div(radius).clamp(-1.0, 1.0);

  GraphInput g;
  g.node_features = torch::cat({velocity.reshape({fluid_count + boundary_count, kVelocityFeatures}),
                                material, fraction, bound_distance},
                               1);
  g.node_type = type;
  g.edge_index = graph.edge_index;
  auto displacement = (position.index_select(0, graph.edge_index[0]) -
                       position.index_select(0, graph.edge_index[1])) /
                      radius;
  g.edge_features = torch::cat({displacement, displacement.norm(2, 1, true)}, 1);
  g.fluid = torch::arange(fluid_count + boundary_count) < fluid_count;
  if (model_->needs_typing()) {
    if (!(particle_radius_ > 0))
      throw std::logic_error(model_->name() +
                             " needs the heterogeneous typing, whose kernel sums need the data's "
                             "particle radius: none was given to the LearnedSimulator");
    const double diameter = 2 * particle_radius_;
    const HeterogeneousTyping typing =
        type_graph(position, type, graph.edge_index, radius, diameter * diameter * diameter,
                   model_->surface_rule());
    g.node_class = typing.node_class;
    g.link_type = typing.link_type;
  }
  const torch::Device device = model_->device();
  return device.is_cpu() ? g : to_device(g, device);
}

NormalisedPrediction LearnedSimulator::predict(const GraphInput& graph, int64_t fluid_count) {
  const ModelOutput out = model_->forward(graph, ForwardOptions{});
  return {out.acceleration.slice(0, 0, fluid_count).to(torch::kCPU),
          out.oil_fraction_change.slice(0, 0, fluid_count).to(torch::kCPU)};
}

torch::Tensor LearnedSimulator::normalise_acceleration(const torch::Tensor& a) const {
  return (a - normalisation_.acc_mean) / normalisation_.acc_std;
}

torch::Tensor LearnedSimulator::denormalise_acceleration(const torch::Tensor& a) const {
  return a * normalisation_.acc_std + normalisation_.acc_mean;
}

torch::Tensor LearnedSimulator::normalise_fraction_change(const torch::Tensor& change) const {
  return change / normalisation_.fraction_change_std;
}

torch::Tensor LearnedSimulator::denormalise_fraction_change(const torch::Tensor& normalised) const {
  return normalised * normalisation_.fraction_change_std;
}

NextState LearnedSimulator::next_state(const FrameNodes& nodes) {
  torch::NoGradGuard no_grad;
  const int64_t fluid_count = nodes.history.size(0);
  const GraphInput graph = encode(nodes);
  const NormalisedPrediction p = predict(graph, fluid_count);
  auto acceleration = denormalise_acceleration(p.acceleration);
  auto last = nodes.history.select(1, kWindow - 1);
  auto velocity = last - nodes.history.select(1, kWindow - 2) + acceleration;
  // Oil moves along the graph's fluid-fluid pairs: within the connectivity radius.
  const auto edges = graph.edge_index.to(torch::kCPU);
  const auto fluid_pairs = edges.index(
      {torch::indexing::Slice(), (edges[0] < fluid_count).logical_and(edges[1] < fluid_count)});
  return {last + velocity,
          local_fraction_update(nodes.oil_fraction,
                                denormalise_fraction_change(p.oil_fraction_change), fluid_pairs)};
}

torch::Tensor local_fraction_update(const torch::Tensor& fraction, const torch::Tensor& change,
                                    const torch::Tensor& pairs) {
  check_tensor("local_fraction_update", "fraction", fraction, {-1}, torch::kFloat32, torch::kCPU,
               /*contiguous=*/false);
  const int64_t n = fraction.size(0);
  check_tensor("local_fraction_update", "change", change, {n}, torch::kFloat32, torch::kCPU,
               /*contiguous=*/false);
  check_tensor("local_fraction_update", "pairs", pairs, {2, -1}, torch::kInt64, torch::kCPU,
               /*contiguous=*/false);
  const auto old = fraction.to(torch::kFloat64);
  const auto delta = change.to(torch::kFloat64);
  // What each particle asks to gain and offers to lose, within what it can take and has.
  const auto gain = torch::minimum(delta.clamp_min(0), 1 - old);
  const auto loss = torch::minimum((-delta).clamp_min(0), old);
  const auto distinct = pairs[0] != pairs[1];
  const auto sender = pairs[0].index({distinct}), receiver = pairs[1].index({distinct});
  const auto offered = loss.index_select(0, sender), asked = gain.index_select(0, receiver);
  // Offers around each receiver and asks around each sender.
  const auto offered_near = torch::zeros({n}, torch::kFloat64).index_add_(0, receiver, offered);
  const auto asked_near = torch::zeros({n}, torch::kFloat64).index_add_(0, sender, asked);
  const auto scale =
      torch::maximum(offered_near.index_select(0, receiver), asked_near.index_select(0, sender));
  const auto flux =
      torch::where(scale > 0, asked * offered / scale.clamp_min(1e-300), torch::zeros_like(scale));
  auto updated = old.clone();
  updated.index_add_(0, receiver, flux).index_add_(0, sender, -flux);
  // Only rounding can take a fraction past its bounds here.
  return updated.clamp(0, 1).to(torch::kFloat32);
}

}  // namespace gnn
