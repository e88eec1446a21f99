#include "infer/side_by_side.h"

#include "sph/image_writer.h"

namespace infer {

struct SideBySideRenderer::Impl {
  sph::FrameRenderer renderer;
  torch::Tensor type;
};

namespace {
std::vector<sph::Vec3> points(const torch::Tensor& p) {
  auto c = p.to(torch::kFloat32).contiguous();
  std::vector<sph::Vec3> out(size_t(c.size(0)));
  const float* d = c.data_ptr<float>();
  for (size_t i = 0; i < out.size(); ++i) out[i] = sph::Vec3(d[3 * i], d[3 * i + 1], d[3 * i + 2]);
  return out;
}
}  // namespace

SideBySideRenderer::SideBySideRenderer(const gnn::Trajectory& t, const gnn::DatasetMetadata& m,
                                       int width) {
  sph::Aabb bounds;
  for (int k = 0; k < 3; ++k) {
    bounds.min[k] = sph::Real(m.bounds[size_t(k)][0]);
    bounds.max[k] = sph::Real(m.bounds[size_t(k)][1]);
  }
  impl_ = std::make_shared<Impl>(
      Impl{sph::FrameRenderer(points(t.boundary), bounds, sph::Real(m.particle_radius), width),
           t.particle_type});
}

void SideBySideRenderer::write(const std::string& png, const torch::Tensor& truth,
                               const torch::Tensor& truth_active, const torch::Tensor& predicted,
                               const torch::Tensor& predicted_active) const {
  auto view = [&](const torch::Tensor& position, const torch::Tensor& active) {
    auto ids = active.nonzero().view(-1);
    auto types = impl_->type.index_select(0, ids).to(torch::kInt32).contiguous();
    std::vector<std::int32_t> type(types.data_ptr<std::int32_t>(),
                                   types.data_ptr<std::int32_t>() + types.numel());
    return impl_->renderer.render(points(position.index_select(0, ids)), type,
                                  sph::ViewAxis::kRiver);
  };
  const sph::RgbImage left = view(truth, truth_active), right = view(predicted, predicted_active);
  const int gap = 8;
  sph::RgbImage out;
  out.width = left.width + gap + right.width;
  out.height = std::max(left.height, right.height);
  out.pixels.assign(size_t(out.width) * size_t(out.height) * 3, 255);
  for (int y = 0; y < out.height; ++y) {
    for (int x = 0; x < left.width && y < left.height; ++x)
      for (int c = 0; c < 3; ++c)
        out.pixels[(size_t(y) * size_t(out.width) + size_t(x)) * 3 + size_t(c)] =
            left.pixels[(size_t(y) * size_t(left.width) + size_t(x)) * 3 + size_t(c)];
    for (int x = 0; x < right.width && y < right.height; ++x)
      for (int c = 0; c < 3; ++c)
        out.pixels[(size_t(y) * size_t(out.width) + size_t(x + left.width + gap)) * 3 + size_t(c)] =
            right.pixels[(size_t(y) * size_t(right.width) + size_t(x)) * 3 + size_t(c)];
  }
  sph::write_png(png, out);
}

}  // namespace infer
