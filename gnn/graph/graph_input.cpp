#include "gnn/graph/graph_input.h"

#include <sstream>
#include <stdexcept>

namespace gnn {

namespace {

std::string sizes_text(const std::vector<int64_t>& sizes) {
  std::ostringstream s;
  s << "[";
  for (size_t k = 0; k < sizes.size(); ++k) {
    if (k) s << ", ";
    if (sizes[k] < 0)
      s << "*";
    else
      s << sizes[k];
  }
  s << "]";
  return s.str();
}

}  // namespace

void check_tensor(const std::string& where, const std::string& name, const torch::Tensor& t,
                  const std::vector<int64_t>& sizes, torch::ScalarType dtype,
                  const torch::Device& device, bool contiguous) {
  auto fail = [&](const std::string& what) {
    throw std::invalid_argument(where + ": " + name + ": " + what);
  };
  if (!t.defined()) fail("is missing");
  bool shape_ok = t.dim() == int64_t(sizes.size());
  for (size_t k = 0; shape_ok && k < sizes.size(); ++k)
    shape_ok = sizes[k] < 0 || t.size(int64_t(k)) == sizes[k];
  if (!shape_ok)
    fail("expected sizes " + sizes_text(sizes) + ", got " + sizes_text(t.sizes().vec()));
  if (t.scalar_type() != dtype)
    fail(std::string("expected dtype ") + c10::toString(dtype) + ", got " +
         c10::toString(t.scalar_type()));
  if (contiguous && !t.is_contiguous())
    fail("expected a contiguous tensor (sizes " + sizes_text(t.sizes().vec()) + ")");
  if (t.device() != device) fail("expected it on " + device.str() + ", got " + t.device().str());
}

void check_graph_input(const GraphInput& g, const std::string& where) {
  if (!g.node_features.defined())
    throw std::invalid_argument(where + ": graph input node_features: is missing");
  // Every tensor on the device of node_features.
  const torch::Device device = g.node_features.device();
  auto check = [&](const char* name, const torch::Tensor& t, std::vector<int64_t> sizes,
                   torch::ScalarType dtype) {
    check_tensor(where, std::string("graph input ") + name, t, sizes, dtype, device);
  };
  check("node_features", g.node_features, {-1, kNodeFeatures}, torch::kFloat32);
  const int64_t n = g.node_features.size(0);
  check("node_type", g.node_type, {n}, torch::kInt64);
  check("edge_index", g.edge_index, {2, -1}, torch::kInt64);
  const int64_t e = g.edge_index.size(1);
  check("edge_features", g.edge_features, {e, kEdgeFeatures}, torch::kFloat32);
  check("fluid", g.fluid, {n}, torch::kBool);
  if (g.node_class.defined()) check("node_class", g.node_class, {n}, torch::kInt64);
  if (g.link_type.defined()) check("link_type", g.link_type, {e}, torch::kInt64);
}

GraphInput to_device(const GraphInput& g, const torch::Device& device) {
  auto move = [&](const torch::Tensor& t) { return t.defined() ? t.to(device) : t; };
  GraphInput out;
  out.node_features = move(g.node_features);
  out.node_type = move(g.node_type);
  out.edge_index = move(g.edge_index);
  out.edge_features = move(g.edge_features);
  out.fluid = move(g.fluid);
  out.node_class = move(g.node_class);
  out.link_type = move(g.link_type);
  return out;
}

}  // namespace gnn
