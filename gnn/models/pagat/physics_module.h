#pragma once
// PAGATNet's physics-aware module (docs/models.md, "Physics-aware module"): per edge a relation
// vector of the pair's physical quantities,
//   r_ij = [ (x_j - x_i) / R (3), |x_j - x_i| / R, (v_j - v_i) normalised (3),
//            density ratio_j - ratio_i, viscosity ratio_j - ratio_i,
//            surface_i, surface_j, one-hot link type (4) ]          (15 values),
// encoded by an MLP to P_ij and projected by each of the chi heads, P'_ij,k = W^k P_ij, to a
// scalar bias per head that is added to that head's attention score in every block (the module's
// weights are shared by all blocks, so it is run once per forward pass). The paper's W^k followed
// by the scalar read-out of a head is one linear map per head; they are stored together as one
// Linear from P to the heads.

#include <torch/torch.h>

#include "gnn/graph/graph_input.h"
#include "gnn/models/mlp.h"

namespace gnn {

constexpr int64_t kRelationFeatures = 15;

// The relation vectors [E, 15] of a typed graph (node_class and link_type defined).
torch::Tensor relation_vectors(const GraphInput& graph);

class PhysicsModuleImpl : public torch::nn::Module {
 public:
  PhysicsModuleImpl(int64_t width, int64_t heads);
  // Per-head attention biases [E, heads] from the relation vectors [E, 15].
  torch::Tensor forward(const torch::Tensor& relations);
  double flops_per_edge() const;

 private:
  Mlp encoder_{nullptr};
  torch::nn::Linear heads_{nullptr};
};
TORCH_MODULE(PhysicsModule);

}  // namespace gnn
