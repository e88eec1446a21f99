#include "gnn/models/learned_simulator.h"

#include "gnn/data/frame_window.h"
#include "gnn/graph/radius_graph.h"

#include <stdexcept>
#include <vector>

namespace gnn {

LearnedSimulator::LearnedSimulator(std::shared_ptr<GraphModel> model, Normalisation normalisation,
                                   Bounds bounds)
    : model_(std::move(model)), normalisation_(std::move(normalisation)), bounds_(bounds) {
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
  check("type", f.type, {n}, torch::kInt64);
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

  auto type = torch::cat({f.type, torch::full({boundary_count}, kBoundary, torch::kInt64)});
  auto material = f.material.index_select(0, type);

  // Distances to the domain's faces in radii, clipped to [-1, 1]: a wall is felt only within
  // reach of the graph.
  auto lower = torch::tensor({float(bounds_[0][0]), float(bounds_[1][0]), float(bounds_[2][0])});
  auto upper = torch::tensor({float(bounds_[0][1]), float(bounds_[1][1]), float(bounds_[2][1])});
  auto bound_distance =
      torch::cat({position - lower, upper - position}, 1).div(radius).clamp(-1.0, 1.0);

  GraphInput g;
  g.node_features = torch::cat({velocity.reshape({fluid_count + boundary_count, kVelocityFeatures}),
                                material, bound_distance},
                               1);
  g.node_type = type;
  g.edge_index = graph.edge_index;
  auto displacement = (position.index_select(0, graph.edge_index[0]) -
                       position.index_select(0, graph.edge_index[1])) /
                      radius;
  g.edge_features = torch::cat({displacement, displacement.norm(2, 1, true)}, 1);
  g.fluid = torch::arange(fluid_count + boundary_count) < fluid_count;
  if (model_->needs_typing())
    throw std::logic_error(model_->name() +
                           " needs the heterogeneous typing, which is not built yet");
  const torch::Device device = model_->device();
  return device.is_cpu() ? g : to_device(g, device);
}

torch::Tensor LearnedSimulator::predict_normalised(const FrameNodes& nodes) {
  const int64_t fluid_count = nodes.history.size(0);
  return model_->acceleration(encode(nodes)).slice(0, 0, fluid_count).to(torch::kCPU);
}

torch::Tensor LearnedSimulator::normalise_acceleration(const torch::Tensor& a) const {
  return (a - normalisation_.acc_mean) / normalisation_.acc_std;
}

torch::Tensor LearnedSimulator::denormalise_acceleration(const torch::Tensor& a) const {
  return a * normalisation_.acc_std + normalisation_.acc_mean;
}

torch::Tensor LearnedSimulator::next_position(const FrameNodes& nodes) {
  torch::NoGradGuard no_grad;
  auto acceleration = denormalise_acceleration(predict_normalised(nodes));
  auto last = nodes.history.select(1, kWindow - 1);
  auto velocity = last - nodes.history.select(1, kWindow - 2) + acceleration;
  return last + velocity;
}

}  // namespace gnn
