#include "infer/side_by_side.h"

#include "common/image_writer.h"

namespace infer {

struct SideBySideRenderer::Impl {
  common::FrameRenderer renderer;
  torch::Tensor type;
};

namespace {
std::vector<common::Point> points(const torch::Tensor& p) {
  auto c = p.to(torch::kFloat32).contiguous();
  std::vector<common::Point> out(size_t(c.size(0)));
  const float* d = c.data_ptr<float>();
  for (size_t i = 0; i < out.size(); ++i)
    out[i] = common::Point(d[3 * i], d[3 * i + 1], d[3 * i + 2]);
  return out;
}
}  // namespace

SideBySideRenderer::SideBySideRenderer(const gnn::Trajectory& t, const gnn::DatasetMetadata& m,
                                       int width) {
  common::Bounds bounds;
  for (int k = 0; k < 3; ++k) {
    bounds.min[k] = float(m.bounds[size_t(k)][0]);
    bounds.max[k] = float(m.bounds[size_t(k)][1]);
  }
  impl_ = std::make_shared<Impl>(
      Impl{common::FrameRenderer(points(t.boundary), bounds, float(m.particle_radius), width),
           t.particle_type});
}

void SideBySideRenderer::write(const std::string& png, const torch::Tensor& truth,
                               const torch::Tensor& truth_active, const torch::Tensor& predicted,
                               const torch::Tensor& predicted_active) const {
  auto view = [&](const torch::Tensor& position, const torch::Tensor& active) {
    auto ids = active.nonzero().view(-1);
    auto oil = (impl_->type.index_select(0, ids) == gnn::kOil).to(torch::kUInt8).contiguous();
    std::vector<std::uint8_t> type(oil.data_ptr<std::uint8_t>(),
                                   oil.data_ptr<std::uint8_t>() + oil.numel());
    return impl_->renderer.render(points(position.index_select(0, ids)), type,
                                  common::ViewAxis::kRiver);
  };
  const common::RgbImage left = view(truth, truth_active),
                         right = view(predicted, predicted_active);
  const int gap = 8;
  common::RgbImage out;
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
  common::write_png(png, out);
}

}  // namespace infer
