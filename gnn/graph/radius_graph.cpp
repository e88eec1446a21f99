#include "gnn/graph/radius_graph.h"

#include <vector>

#include "sph/core/neighbour_grid.h"

namespace gnn {
namespace {

std::vector<sph::Vec3> to_points(const torch::Tensor& positions) {
  auto p = positions.to(torch::kFloat32).contiguous();
  const float* d = p.data_ptr<float>();
  std::vector<sph::Vec3> out(size_t(p.size(0)));
  for (size_t i = 0; i < out.size(); ++i)
    out[i] = sph::Vec3(sph::Real(d[3 * i]), sph::Real(d[3 * i + 1]), sph::Real(d[3 * i + 2]));
  return out;
}

// A box around all points, a radius wider on every side, so no point falls outside the grid
// even when a rollout carries particles past the dataset's bounds.
sph::Aabb box_around(const std::vector<sph::Vec3>& a, const std::vector<sph::Vec3>& b,
                     double radius) {
  sph::Aabb box;
  box.min = sph::Vec3::Constant(std::numeric_limits<sph::Real>::max());
  box.max = sph::Vec3::Constant(std::numeric_limits<sph::Real>::lowest());
  for (const auto* set : {&a, &b})
    for (const auto& p : *set) {
      box.min = box.min.cwiseMin(p);
      box.max = box.max.cwiseMax(p);
    }
  if (a.empty() && b.empty()) box.min = box.max = sph::Vec3::Zero();
  box.min.array() -= sph::Real(radius);
  box.max.array() += sph::Real(radius);
  return box;
}

torch::Tensor to_tensor(const std::vector<int64_t>& v) {
  return torch::from_blob(const_cast<int64_t*>(v.data()), {int64_t(v.size())}, torch::kInt64)
      .clone();
}

}  // namespace

namespace {

RadiusGraph build_unchecked(const torch::Tensor& fluid_positions,
                            const torch::Tensor& boundary_positions, double radius) {
  const auto fluid = to_points(fluid_positions);
  const auto boundary = to_points(boundary_positions);
  for (const auto& p : fluid)
    if (!p.allFinite()) throw std::runtime_error("radius graph: a fluid position is not finite");
  const sph::Aabb box = box_around(fluid, boundary, radius);

  // Boundary particles within reach of the fluid become nodes.
  std::vector<int64_t> kept;
  if (!boundary.empty() && !fluid.empty()) {
    sph::NeighbourGrid fluid_grid(box, sph::Real(radius));
    fluid_grid.build(fluid);
    for (size_t b = 0; b < boundary.size(); ++b) {
      bool near = false;
      fluid_grid.for_each_near(boundary[b], [&](sph::Index) { near = true; });
      if (near) kept.push_back(int64_t(b));
    }
  }
  std::vector<sph::Vec3> nodes = fluid;
  for (int64_t b : kept) nodes.push_back(boundary[size_t(b)]);

  sph::NeighbourGrid grid(box, sph::Real(radius));
  grid.build(nodes);
  sph::NeighbourLists lists;
  grid.find(nodes.data(), sph::Index(nodes.size()), /*same_set=*/true, lists);
  const int64_t fluid_count = int64_t(fluid.size());
  std::vector<int64_t> senders, receivers;
  senders.reserve(lists.pairs());
  receivers.reserve(lists.pairs());
  for (sph::Index i = 0; i < lists.queries(); ++i) {
    std::vector<int64_t> row;
    lists.for_each(i, [&](sph::Index j) {
      if (int64_t(i) < fluid_count || int64_t(j) < fluid_count) row.push_back(int64_t(j));
    });
    std::sort(row.begin(), row.end());  // a canonical order, independent of the grid's cells
    for (int64_t j : row) {
      senders.push_back(j);
      receivers.push_back(int64_t(i));
    }
  }
  RadiusGraph g;
  g.boundary_nodes = to_tensor(kept);
  g.edge_index = torch::stack({to_tensor(senders), to_tensor(receivers)});
  return g;
}

}  // namespace

RadiusGraph brute_force_radius_graph(const torch::Tensor& fluid_positions,
                                     const torch::Tensor& boundary_positions, double radius) {
  const auto fluid = to_points(fluid_positions);
  const auto boundary = to_points(boundary_positions);
  const sph::Real r2 = sph::Real(radius) * sph::Real(radius);
  auto close = [&](const sph::Vec3& a, const sph::Vec3& b) {
    const sph::Real dx = b[0] - a[0], dy = b[1] - a[1], dz = b[2] - a[2];
    return dx * dx + dy * dy + dz * dz < r2;
  };
  std::vector<int64_t> kept;
  for (size_t b = 0; b < boundary.size(); ++b)
    for (const auto& f : fluid)
      if (close(f, boundary[b])) {
        kept.push_back(int64_t(b));
        break;
      }
  std::vector<sph::Vec3> nodes = fluid;
  for (int64_t b : kept) nodes.push_back(boundary[size_t(b)]);
  const int64_t fluid_count = int64_t(fluid.size());
  std::vector<int64_t> senders, receivers;
  for (int64_t i = 0; i < int64_t(nodes.size()); ++i)
    for (int64_t j = 0; j < int64_t(nodes.size()); ++j)
      if (i != j && (i < fluid_count || j < fluid_count) &&
          close(nodes[size_t(i)], nodes[size_t(j)])) {
        senders.push_back(j);
        receivers.push_back(i);
      }
  RadiusGraph g;
  g.boundary_nodes = to_tensor(kept);
  g.edge_index = torch::stack({to_tensor(senders), to_tensor(receivers)});
  return g;
}

RadiusGraph build_radius_graph(const torch::Tensor& fluid_positions,
                               const torch::Tensor& boundary_positions, double radius) {
  try {
    return build_unchecked(fluid_positions, boundary_positions, radius);
  } catch (const sph::PointOutsideDomain& e) {
    // The grid spans the points themselves, so only coordinates too large for its float cells
    // get here: a rollout that has blown up, or positions no simulator wrote.
    const sph::Vec3 p = e.point();
    throw std::runtime_error("radius graph: a position (" + std::to_string(p[0]) + ", " +
                             std::to_string(p[1]) + ", " + std::to_string(p[2]) +
                             ") is too far out for a neighbour grid of radius " +
                             std::to_string(radius));
  }
}

}  // namespace gnn
