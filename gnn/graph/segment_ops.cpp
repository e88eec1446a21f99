#include "gnn/graph/segment_ops.h"

namespace gnn {
namespace {

// out[i] = sum of rows offsets[i] .. offsets[i+1] of `values`, or with `permutation` of rows
// permutation[offsets[i]] .. permutation[offsets[i+1] - 1].
torch::Tensor csr_sum(const torch::Tensor& values_in, const torch::Tensor& offsets,
                      const int64_t* permutation = nullptr) {
  auto values = values_in.contiguous();
  const int64_t n = offsets.size(0) - 1, width = values.size(1);
  auto out = torch::empty({n, width}, values.options());
  const float* v = values.data_ptr<float>();
  float* o = out.data_ptr<float>();
  const int64_t* off = offsets.data_ptr<int64_t>();
  at::parallel_for(0, n, 256, [&](int64_t begin, int64_t end) {
    for (int64_t i = begin; i < end; ++i) {
      float* row = o + i * width;
      for (int64_t c = 0; c < width; ++c) row[c] = 0;
      for (int64_t k = off[i]; k < off[i + 1]; ++k) {
        const float* src = v + (permutation ? permutation[k] : k) * width;
        for (int64_t c = 0; c < width; ++c) row[c] += src[c];
      }
    }
  });
  return out;
}

using torch::autograd::AutogradContext;
using torch::autograd::variable_list;

struct GatherReceivers : torch::autograd::Function<GatherReceivers> {
  static torch::Tensor forward(AutogradContext* ctx, const torch::Tensor& values,
                               const torch::Tensor& receivers, const torch::Tensor& offsets) {
    ctx->save_for_backward({offsets});
    return values.index_select(0, receivers);
  }
  static variable_list backward(AutogradContext* ctx, variable_list grad) {
    return {csr_sum(grad[0], ctx->get_saved_variables()[0]), torch::Tensor(), torch::Tensor()};
  }
};

struct GatherSenders : torch::autograd::Function<GatherSenders> {
  static torch::Tensor forward(AutogradContext* ctx, const torch::Tensor& values,
                               const torch::Tensor& senders, const torch::Tensor& offsets,
                               const torch::Tensor& reverse) {
    ctx->save_for_backward({offsets, reverse});
    return values.index_select(0, senders);
  }
  static variable_list backward(AutogradContext* ctx, variable_list grad) {
    auto saved = ctx->get_saved_variables();
    return {csr_sum(grad[0].index_select(0, saved[1]), saved[0]), torch::Tensor(), torch::Tensor(),
            torch::Tensor()};
  }
};

struct SumToReceivers : torch::autograd::Function<SumToReceivers> {
  static torch::Tensor forward(AutogradContext* ctx, const torch::Tensor& edge_values,
                               const torch::Tensor& receivers, const torch::Tensor& offsets) {
    ctx->save_for_backward({receivers});
    return csr_sum(edge_values, offsets);
  }
  static variable_list backward(AutogradContext* ctx, variable_list grad) {
    return {grad[0].index_select(0, ctx->get_saved_variables()[0]), torch::Tensor(),
            torch::Tensor()};
  }
};

}  // namespace

EdgeOrder edge_order(const torch::Tensor& edge_index, int64_t nodes) {
  EdgeOrder o;
  o.senders = edge_index[0].contiguous();
  o.receivers = edge_index[1].contiguous();
  const int64_t E = o.senders.size(0);
  o.offsets = torch::zeros({nodes + 1}, torch::kInt64);
  if (E == 0) {
    o.reverse = torch::zeros({0}, torch::kInt64);
    o.canonical = true;
    return o;
  }
  // Sorted by (receiver, sender): the key receiver * n + sender increases strictly.
  auto key = o.receivers * nodes + o.senders;
  if (!(key.slice(0, 1) > key.slice(0, 0, E - 1)).all().item<bool>()) return o;
  o.offsets.slice(0, 1) = torch::bincount(o.receivers, {}, nodes).cumsum(0);
  auto reversed_key = o.senders * nodes + o.receivers;
  o.reverse = torch::searchsorted(key, reversed_key);
  o.canonical = (o.reverse < E).all().item<bool>() &&
                torch::equal(key.index_select(0, o.reverse.clamp_max(E - 1)), reversed_key);
  return o;
}

torch::Tensor csr_sum_by_receiver(const torch::Tensor& edge_values, const EdgeOrder& o) {
  return csr_sum(edge_values, o.offsets);
}

// The edges with sender i are the reverses of the edges with receiver i.
torch::Tensor csr_sum_by_sender(const torch::Tensor& edge_values, const EdgeOrder& o) {
  return csr_sum(edge_values, o.offsets, o.reverse.data_ptr<int64_t>());
}

torch::Tensor gather_receivers(const torch::Tensor& values, const EdgeOrder& o) {
  if (!o.canonical || values.scalar_type() != torch::kFloat32 || !values.is_cpu())
    return values.index_select(0, o.receivers);
  return GatherReceivers::apply(values, o.receivers, o.offsets);
}

torch::Tensor gather_senders(const torch::Tensor& values, const EdgeOrder& o) {
  if (!o.canonical || values.scalar_type() != torch::kFloat32 || !values.is_cpu())
    return values.index_select(0, o.senders);
  return GatherSenders::apply(values, o.senders, o.offsets, o.reverse);
}

torch::Tensor sum_to_receivers(const torch::Tensor& edge_values, const EdgeOrder& o,
                               int64_t nodes) {
  if (!o.canonical || edge_values.scalar_type() != torch::kFloat32 || !edge_values.is_cpu())
    return torch::zeros({nodes, edge_values.size(1)}, edge_values.options())
        .index_add_(0, o.receivers, edge_values);
  return SumToReceivers::apply(edge_values, o.receivers, o.offsets);
}

torch::Tensor segment_sum(const torch::Tensor& values, const torch::Tensor& receivers,
                          const torch::Tensor& offsets) {
  const int64_t nodes = offsets.size(0) - 1;
  if (values.scalar_type() == torch::kFloat32 && values.is_cpu())
    return SumToReceivers::apply(values, receivers, offsets);
  return torch::zeros({nodes, values.size(1)}, values.options()).index_add_(0, receivers, values);
}

torch::Tensor segment_softmax(const torch::Tensor& scores, const torch::Tensor& receivers,
                              const torch::Tensor& offsets) {
  torch::Tensor largest;
  {
    torch::NoGradGuard no_grad;
    largest = at::segment_reduce(scores.detach(), "max", {}, {}, offsets);  // [n, H]
  }
  const auto shifted = torch::exp(scores - largest.index_select(0, receivers));
  const auto denominator = segment_sum(shifted, receivers, offsets);
  const bool csr = scores.scalar_type() == torch::kFloat32 && scores.is_cpu();
  return shifted / (csr ? GatherReceivers::apply(denominator, receivers, offsets)
                        : denominator.index_select(0, receivers));
}

}  // namespace gnn
