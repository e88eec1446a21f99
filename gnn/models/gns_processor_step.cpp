#include "gnn/models/gns_processor_step.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "gnn/models/row_chunks.h"

namespace gnn {
namespace {

using torch::autograd::AutogradContext;
using torch::autograd::variable_list;

// Where each tensor sits in the step's flat input list, for MLPs of `m` Linear layers:
// v, e, W_rs, edge MLP (W_0..W_m-1, b_0..b_m-1, gamma, beta), W_a, node MLP (likewise).
struct InputLayout {
  int64_t m;
  static constexpr int64_t kV = 0, kE = 1, kReceiverSender = 2;
  int64_t w(bool edge, int64_t l) const { return (edge ? 3 : 6 + 2 * m) + l; }
  int64_t b(bool edge, int64_t l) const { return (edge ? 3 : 6 + 2 * m) + m + l; }
  int64_t gamma(bool edge) const { return (edge ? 3 : 6 + 2 * m) + 2 * m; }
  int64_t beta(bool edge) const { return gamma(edge) + 1; }
  int64_t aggregate() const { return 5 + 2 * m; }
  int64_t count() const { return 8 + 4 * m; }
};

// LayerNorm of z + bias per row, keeping what the backward pass needs: z becomes the
// normalised values, rstd[r] 1/std, y the output.
void add_bias_layer_norm_for_backward(float* z, const float* bias, const float* gamma,
                                      const float* beta, float eps, float* rstd, float* y,
                                      int64_t rows, int64_t width) {
  for (int64_t r = 0; r < rows; ++r, z += width, y += width) {
    const auto [mean, inv] = layer_norm_statistics(z, bias, width, eps);
    rstd[r] = inv;
#pragma omp simd
    for (int64_t c = 0; c < width; ++c) {
      z[c] = (z[c] + bias[c] - mean) * inv;
      y[c] = z[c] * gamma[c] + beta[c];
    }
  }
}

// LayerNorm backward per row: gz from gy; adds the gamma and beta gradients to dgamma, dbeta.
void layer_norm_backward(const float* gy, const float* z_hat, const float* rstd, const float* gamma,
                         float* gz, float* dgamma, float* dbeta, int64_t rows, int64_t width) {
  for (int64_t r = 0; r < rows; ++r, gy += width, z_hat += width, gz += width) {
    float mean_g = 0, mean_gz = 0;
#pragma omp simd reduction(+ : mean_g, mean_gz)
    for (int64_t c = 0; c < width; ++c) {
      const float g = gy[c] * gamma[c];
      mean_g += g;
      mean_gz += g * z_hat[c];
    }
    mean_g /= float(width);
    mean_gz /= float(width);
    const float inv = rstd[r];
#pragma omp simd
    for (int64_t c = 0; c < width; ++c) {
      dgamma[c] += gy[c] * z_hat[c];
      dbeta[c] += gy[c];
      gz[c] = inv * (gy[c] * gamma[c] - mean_g - z_hat[c] * mean_gz);
    }
  }
}

// acc += column sums of x.
void add_column_sums(const float* x, float* acc, int64_t rows, int64_t width) {
  for (int64_t r = 0; r < rows; ++r, x += width)
#pragma omp simd
    for (int64_t c = 0; c < width; ++c) acc[c] += x[c];
}

// g = 0 where the ReLU's output a was 0 (its mask), as a select the compiler vectorises.
void relu_mask(float* g, const float* a, int64_t count) {
#pragma omp simd
  for (int64_t k = 0; k < count; ++k) g[k] = a[k] > 0.0f ? g[k] : 0.0f;
}

// Per-thread sums of the parameter gradients, added up at the end (chunks on different threads
// may not add into the same tensor).
class GradientSums {
 public:
  GradientSums(const variable_list& inputs, std::vector<int64_t> slots)
      : inputs_(inputs), slots_(std::move(slots)), per_thread_(size_t(at::get_num_threads())) {}
  // The sum for input `slot` on `thread`, zero-initialised on first use.
  torch::Tensor tensor(int thread, int64_t slot) {
    auto& sums = per_thread_[size_t(thread)];
    if (sums.empty())
      for (int64_t s : slots_) sums.push_back(torch::zeros_like(inputs_[size_t(s)]));
    return sums[size_t(std::find(slots_.begin(), slots_.end(), slot) - slots_.begin())];
  }
  float* at(int thread, int64_t slot) { return tensor(thread, slot).data_ptr<float>(); }
  // Writes the totals into grad[slot].
  void write(variable_list& grad) const {
    for (size_t k = 0; k < slots_.size(); ++k) {
      torch::Tensor total;
      for (const auto& sums : per_thread_)
        if (!sums.empty()) total = total.defined() ? total + sums[k] : sums[k];
      grad[size_t(slots_[k])] =
          total.defined() ? total : torch::zeros_like(inputs_[size_t(slots_[k])]);
    }
  }

 private:
  const variable_list& inputs_;
  std::vector<int64_t> slots_;
  std::vector<std::vector<torch::Tensor>> per_thread_;
};

// What one MLP keeps for its backward: each ReLU's output (act[l] is Linear l+1's input) and
// the LayerNorm's normalised values and 1/std per row.
struct MlpSaved {
  std::vector<torch::Tensor> act;
  torch::Tensor z_hat, rstd;
};

// Forward of an MLP over `rows` rows in chunks. first(c0, c1, x) writes the first Linear's
// output without its bias into x ([c1 - c0, L]); the rest (bias, ReLU, later Linears, LayerNorm)
// follows here. The output goes to y [rows, L].
template <class First>
MlpSaved mlp_forward(const variable_list& in, const InputLayout& lo, bool edge, int64_t rows,
                     float eps, torch::Tensor& y, const First& first) {
  const int64_t L = in[size_t(lo.w(edge, 0))].size(0);
  MlpSaved saved;
  for (int64_t l = 0; l + 1 < lo.m; ++l) saved.act.push_back(torch::empty({rows, L}));
  saved.z_hat = torch::empty({rows, L});
  saved.rstd = torch::empty({rows});
  for_chunks(chunk_count(rows), [&](int64_t first_chunk, int64_t last_chunk, int) {
    torch::NoGradGuard no_grad;  // grad mode is per thread
    for (int64_t c = first_chunk; c < last_chunk; ++c) {
      const int64_t c0 = c * kChunk, c1 = std::min(rows, c0 + kChunk), n = c1 - c0;
      auto x = saved.act[0].slice(0, c0, c1);
      first(c0, c1, x);
      add_bias_relu(x.data_ptr<float>(), in[size_t(lo.b(edge, 0))].data_ptr<float>(), n, L);
      for (int64_t l = 1; l < lo.m; ++l) {
        const bool last = l + 1 == lo.m;
        auto out = last ? saved.z_hat.slice(0, c0, c1) : saved.act[size_t(l)].slice(0, c0, c1);
        at::mm_out(out, saved.act[size_t(l - 1)].slice(0, c0, c1), in[size_t(lo.w(edge, l))].t());
        const float* bias = in[size_t(lo.b(edge, l))].data_ptr<float>();
        if (!last) {
          add_bias_relu(out.data_ptr<float>(), bias, n, L);
        } else {
          add_bias_layer_norm_for_backward(
              out.data_ptr<float>(), bias, in[size_t(lo.gamma(edge))].data_ptr<float>(),
              in[size_t(lo.beta(edge))].data_ptr<float>(), eps, saved.rstd.data_ptr<float>() + c0,
              y.data_ptr<float>() + c0 * L, n, L);
        }
      }
    }
  });
  return saved;
}

// Backward of mlp_forward in chunks. gy(c0, c1, out) writes the output's gradient for the rows
// into out; first(c0, c1, g, thread) receives the gradient with respect to the first Linear's
// output (ReLU mask applied, bias gradient already summed) and handles that layer's inputs.
template <class OutputGradient, class First>
void mlp_backward(const variable_list& in, const InputLayout& lo, bool edge, int64_t rows,
                  const MlpSaved& saved, GradientSums& sums, const OutputGradient& gy,
                  const First& first) {
  const int64_t L = in[size_t(lo.w(edge, 0))].size(0);
  for_chunks(chunk_count(rows), [&](int64_t first_chunk, int64_t last_chunk, int thread) {
    torch::NoGradGuard no_grad;
    auto a = torch::empty({kChunk, L}), b = torch::empty({kChunk, L});
    for (int64_t c = first_chunk; c < last_chunk; ++c) {
      const int64_t c0 = c * kChunk, c1 = std::min(rows, c0 + kChunk), n = c1 - c0;
      auto g_out = a.slice(0, 0, n), g = b.slice(0, 0, n);
      gy(c0, c1, g_out);
      layer_norm_backward(g_out.data_ptr<float>(), saved.z_hat.data_ptr<float>() + c0 * L,
                          saved.rstd.data_ptr<float>() + c0,
                          in[size_t(lo.gamma(edge))].data_ptr<float>(), g.data_ptr<float>(),
                          sums.at(thread, lo.gamma(edge)), sums.at(thread, lo.beta(edge)), n, L);
      for (int64_t l = lo.m - 1; l >= 1; --l) {
        const auto act = saved.act[size_t(l - 1)].slice(0, c0, c1);
        auto dw = sums.tensor(thread, lo.w(edge, l));
        dw.addmm_(g.t(), act);
        add_column_sums(g.data_ptr<float>(), sums.at(thread, lo.b(edge, l)), n, L);
        at::mm_out(g_out, g, in[size_t(lo.w(edge, l))]);
        relu_mask(g_out.data_ptr<float>(), act.data_ptr<float>(), n * L);
        std::swap(g_out, g);
      }
      add_column_sums(g.data_ptr<float>(), sums.at(thread, lo.b(edge, 0)), n, L);
      first(c0, c1, g, thread);
    }
  });
}

struct ProcessorStep : torch::autograd::Function<ProcessorStep> {
  static variable_list forward(AutogradContext* ctx, at::TensorList inputs, int64_t linears,
                               double edge_eps, double node_eps, const EdgeOrder& order) {
    const InputLayout lo{linears};
    const variable_list in(inputs.begin(), inputs.end());
    const auto& v = in[InputLayout::kV];
    const auto& e = in[InputLayout::kE];
    const int64_t n = v.size(0), E = e.size(0), L = v.size(1);

    // Edge MLP: its first Linear on [e_ij, v_receiver, v_sender] split into W_e e_ij and the
    // node projections (W_r v)[receiver] + (W_s v)[sender].
    auto projected = at::mm(v, in[InputLayout::kReceiverSender].t());  // [n, 2L]
    auto r = projected.slice(1, 0, L).contiguous(), s = projected.slice(1, L, 2 * L).contiguous();
    const int64_t* receiver = order.receivers.data_ptr<int64_t>();
    const int64_t* sender = order.senders.data_ptr<int64_t>();
    auto e_update = torch::empty({E, L});
    const MlpSaved edge_saved = mlp_forward(
        in, lo, true, E, float(edge_eps), e_update, [&](int64_t c0, int64_t c1, torch::Tensor& x) {
          at::mm_out(x, e.slice(0, c0, c1), in[size_t(lo.w(true, 0))].t());
          float* px = x.data_ptr<float>();
          const float* pr = r.data_ptr<float>();
          const float* ps = s.data_ptr<float>();
          for (int64_t k = c0; k < c1; ++k, px += L) {
            const float* ra = pr + receiver[k] * L;
            const float* sa = ps + sender[k] * L;
#pragma omp simd
            for (int64_t c = 0; c < L; ++c) px[c] += ra[c] + sa[c];
          }
        });
    auto aggregated = csr_sum_by_receiver(e_update, order);
    auto e_new = e_update.add_(e);  // the residual (the update itself is not needed again)

    // Node MLP on [v, aggregated], its first Linear split likewise.
    auto v_new = torch::empty({n, L});
    const MlpSaved node_saved = mlp_forward(
        in, lo, false, n, float(node_eps), v_new, [&](int64_t c0, int64_t c1, torch::Tensor& x) {
          at::mm_out(x, v.slice(0, c0, c1), in[size_t(lo.w(false, 0))].t());
          x.addmm_(aggregated.slice(0, c0, c1), in[size_t(lo.aggregate())].t());
        });
    v_new.add_(v);

    variable_list saved(in.begin(), in.end());
    saved.push_back(aggregated);
    for (const MlpSaved* m : {&edge_saved, &node_saved}) {
      saved.push_back(m->z_hat);
      saved.push_back(m->rstd);
      for (const auto& a : m->act) saved.push_back(a);
    }
    ctx->save_for_backward(saved);
    ctx->saved_data["linears"] = linears;
    ctx->saved_data["senders"] = order.senders;
    ctx->saved_data["receivers"] = order.receivers;
    ctx->saved_data["offsets"] = order.offsets;
    ctx->saved_data["reverse"] = order.reverse;
    return {v_new, e_new};
  }

  static variable_list backward(AutogradContext* ctx, variable_list grads) {
    const InputLayout lo{ctx->saved_data["linears"].toInt()};
    const variable_list saved = ctx->get_saved_variables();
    const variable_list in(saved.begin(), saved.begin() + lo.count());
    size_t next = size_t(lo.count());
    const auto aggregated = saved[next++];
    MlpSaved edge_saved, node_saved;
    for (MlpSaved* m : {&edge_saved, &node_saved}) {
      m->z_hat = saved[next++];
      m->rstd = saved[next++];
      for (int64_t l = 0; l + 1 < lo.m; ++l) m->act.push_back(saved[next++]);
    }
    EdgeOrder order;
    order.senders = ctx->saved_data["senders"].toTensor();
    order.receivers = ctx->saved_data["receivers"].toTensor();
    order.offsets = ctx->saved_data["offsets"].toTensor();
    order.reverse = ctx->saved_data["reverse"].toTensor();
    order.canonical = true;

    const auto& v = in[InputLayout::kV];
    const auto& e = in[InputLayout::kE];
    const int64_t n = v.size(0), E = e.size(0), L = v.size(1);
    const auto g_v_new = grads[0].contiguous(), g_e_new = grads[1].contiguous();
    variable_list grad(size_t(lo.count()) + 4);  // + the four non-tensor arguments
    std::vector<int64_t> slots;
    for (bool edge : {true, false}) {
      for (int64_t l = 0; l < lo.m; ++l) {
        slots.push_back(lo.w(edge, l));
        slots.push_back(lo.b(edge, l));
      }
      slots.push_back(lo.gamma(edge));
      slots.push_back(lo.beta(edge));
    }
    slots.push_back(lo.aggregate());
    GradientSums sums(in, slots);

    // Node MLP: its output is the residual's update of v.
    auto g_v = torch::empty({n, L}), g_aggregated = torch::empty({n, L});
    mlp_backward(
        in, lo, false, n, node_saved, sums,
        [&](int64_t c0, int64_t c1, torch::Tensor& out) { out.copy_(g_v_new.slice(0, c0, c1)); },
        [&](int64_t c0, int64_t c1, const torch::Tensor& g, int thread) {
          sums.tensor(thread, lo.w(false, 0)).addmm_(g.t(), v.slice(0, c0, c1));
          sums.tensor(thread, lo.aggregate()).addmm_(g.t(), aggregated.slice(0, c0, c1));
          auto gv = g_v.slice(0, c0, c1);
          at::addmm_out(gv, g_v_new.slice(0, c0, c1), g, in[size_t(lo.w(false, 0))]);
          auto ga = g_aggregated.slice(0, c0, c1);
          at::mm_out(ga, g, in[size_t(lo.aggregate())]);
        });

    // Edge MLP: its output reaches the loss through the residual and the aggregation.
    const int64_t* receiver = order.receivers.data_ptr<int64_t>();
    auto g_e = torch::empty({E, L}), g_first = torch::empty({E, L});
    mlp_backward(
        in, lo, true, E, edge_saved, sums,
        [&](int64_t c0, int64_t c1, torch::Tensor& out) {
          float* o = out.data_ptr<float>();
          const float* ge = g_e_new.data_ptr<float>() + c0 * L;
          const float* ga = g_aggregated.data_ptr<float>();
          for (int64_t k = c0; k < c1; ++k, o += L, ge += L) {
            const float* row = ga + receiver[k] * L;
#pragma omp simd
            for (int64_t c = 0; c < L; ++c) o[c] = ge[c] + row[c];
          }
        },
        [&](int64_t c0, int64_t c1, const torch::Tensor& g, int thread) {
          sums.tensor(thread, lo.w(true, 0)).addmm_(g.t(), e.slice(0, c0, c1));
          auto ge = g_e.slice(0, c0, c1);
          at::addmm_out(ge, g_e_new.slice(0, c0, c1), g, in[size_t(lo.w(true, 0))]);
          g_first.slice(0, c0, c1).copy_(g);
        });
    // The node projections' gradients: CSR sums of the first layer's gradient by receiver and
    // by sender.
    auto g_projected = torch::cat(
        {csr_sum_by_receiver(g_first, order), csr_sum_by_sender(g_first, order)}, 1);  // [n, 2L]
    grad[InputLayout::kReceiverSender] = g_projected.t().mm(v);
    g_v.addmm_(g_projected, in[InputLayout::kReceiverSender]);
    sums.write(grad);
    grad[InputLayout::kV] = g_v;
    grad[InputLayout::kE] = g_e;
    return grad;
  }
};

}  // namespace

std::pair<torch::Tensor, torch::Tensor> processor_step_with_lean_backward(
    const torch::Tensor& v, const torch::Tensor& e, MlpImpl& edge_mlp,
    torch::nn::LinearImpl& receiver_sender, MlpImpl& node_mlp, torch::nn::LinearImpl& aggregate,
    const EdgeOrder& order) {
  const int64_t m = int64_t(edge_mlp.linears());
  std::vector<torch::Tensor> in{v.contiguous(), e.contiguous(), receiver_sender.weight};
  for (size_t l = 0; l < edge_mlp.linears(); ++l) in.push_back(edge_mlp.linear(l)->weight);
  for (size_t l = 0; l < edge_mlp.linears(); ++l) in.push_back(edge_mlp.linear(l)->bias);
  in.push_back(edge_mlp.norm()->weight);
  in.push_back(edge_mlp.norm()->bias);
  in.push_back(aggregate.weight);
  for (size_t l = 0; l < node_mlp.linears(); ++l) in.push_back(node_mlp.linear(l)->weight);
  for (size_t l = 0; l < node_mlp.linears(); ++l) in.push_back(node_mlp.linear(l)->bias);
  in.push_back(node_mlp.norm()->weight);
  in.push_back(node_mlp.norm()->bias);
  // As a TensorList: autograd only sees tensors passed as Tensor or TensorList arguments.
  auto out = ProcessorStep::apply(at::TensorList(in), m, edge_mlp.norm()->options.eps(),
                                  node_mlp.norm()->options.eps(), order);
  return {out[0], out[1]};
}

}  // namespace gnn
