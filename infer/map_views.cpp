#include "infer/map_views.h"

#include <algorithm>

namespace infer {

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

MapViewRenderer::MapViewRenderer(const gnn::Trajectory& t, const gnn::DatasetMetadata& m,
                                 int width) {
  common::Bounds bounds;
  for (int k = 0; k < 3; ++k) {
    bounds.min[k] = float(m.bounds[size_t(k)][0]);
    bounds.max[k] = float(m.bounds[size_t(k)][1]);
  }
  renderer_ = std::make_shared<common::FrameRenderer>(points(t.boundary), bounds,
                                                      float(m.particle_radius), width);
}

common::RgbImage MapViewRenderer::render(const torch::Tensor& position, const torch::Tensor& active,
                                         const torch::Tensor& oil_fraction) const {
  auto ids = active.nonzero().view(-1);
  auto oil = (oil_fraction.index_select(0, ids) >= gnn::kOilFractionThreshold)
                 .to(torch::kUInt8)
                 .contiguous();
  std::vector<std::uint8_t> is_oil(oil.data_ptr<std::uint8_t>(),
                                   oil.data_ptr<std::uint8_t>() + oil.numel());
  return renderer_->render(points(position.index_select(0, ids)), is_oil, common::ViewAxis::kRiver);
}

common::RgbImage image_grid(const std::vector<std::vector<common::RgbImage>>& rows, int gap) {
  int cell_w = 0, cell_h = 0, columns = 0;
  for (const auto& row : rows) {
    columns = std::max(columns, int(row.size()));
    for (const auto& image : row) {
      cell_w = std::max(cell_w, image.width);
      cell_h = std::max(cell_h, image.height);
    }
  }
  common::RgbImage out;
  out.width = std::max(0, columns * (cell_w + gap) - gap);
  out.height = std::max(0, int(rows.size()) * (cell_h + gap) - gap);
  out.pixels.assign(size_t(out.width) * size_t(out.height) * 3, 255);
  for (size_t r = 0; r < rows.size(); ++r)
    for (size_t c = 0; c < rows[r].size(); ++c) {
      const common::RgbImage& image = rows[r][c];
      const size_t x0 = c * size_t(cell_w + gap), y0 = r * size_t(cell_h + gap);
      for (int y = 0; y < image.height; ++y)
        std::copy_n(
            image.pixels.begin() + std::ptrdiff_t(size_t(y) * size_t(image.width) * 3),
            size_t(image.width) * 3,
            out.pixels.begin() + std::ptrdiff_t(((y0 + size_t(y)) * size_t(out.width) + x0) * 3));
    }
  return out;
}

}  // namespace infer
