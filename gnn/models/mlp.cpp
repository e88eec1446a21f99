#include "gnn/models/mlp.h"

#include <string>

namespace gnn {

MlpImpl::MlpImpl(int64_t in, int64_t hidden, int64_t out, int hidden_layers, bool layer_norm) {
  int64_t width = in;
  for (int k = 0; k <= hidden_layers; ++k) {
    const int64_t next = k == hidden_layers ? out : hidden;
    layers_.push_back(
        register_module("linear" + std::to_string(k), torch::nn::Linear(width, next)));
    width = next;
  }
  if (layer_norm)
    norm_ = register_module("norm", torch::nn::LayerNorm(torch::nn::LayerNormOptions({out})));
}

torch::Tensor MlpImpl::forward_after_first(torch::Tensor x) {
  // relu_ in place: the Linear before it does not need its output for the backward pass.
  for (size_t k = 1; k < layers_.size(); ++k) x = layers_[k]->forward(torch::relu_(x));
  return norm_ ? norm_->forward(x) : x;
}

torch::Tensor MlpImpl::forward(torch::Tensor x) {
  return forward_after_first(layers_[0]->forward(x));
}

}  // namespace gnn
