#pragma once
// The multilayer perceptron every learned model is built of (GNS, DPI-Nets, PAGATNet).

#include <torch/torch.h>

#include <vector>

namespace gnn {

// A stack of Linear layers with ReLU between them and optional LayerNorm at the end.
class MlpImpl : public torch::nn::Module {
 public:
  MlpImpl(int64_t in, int64_t hidden, int64_t out, int hidden_layers, bool layer_norm);
  torch::Tensor forward(torch::Tensor x);
  // The rest of the MLP after its first Linear has been applied (pre-activation input).
  torch::Tensor forward_after_first(torch::Tensor first_pre_activation);
  torch::nn::Linear first() { return layers_[0]; }
  torch::nn::Linear linear(size_t k) { return layers_[k]; }
  size_t linears() const { return layers_.size(); }
  // Multiply-add FLOPs (2 per multiply-add) of the MLP's Linears for one row.
  double flops_per_row() const {
    double f = 0;
    for (const auto& l : layers_) f += 2.0 * double(l->weight.size(0) * l->weight.size(1));
    return f;
  }
  torch::nn::LayerNorm norm() { return norm_; }

 private:
  std::vector<torch::nn::Linear> layers_;
  torch::nn::LayerNorm norm_{nullptr};
};
TORCH_MODULE(Mlp);

}  // namespace gnn
