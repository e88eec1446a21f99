#include "infer/map_views.h"

#include <algorithm>
#include <map>
#include <set>

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
  top_ = bounds.max[2];
}

common::RgbImage MapViewRenderer::render_oiling(const std::vector<gnn::RolloutResult>& members,
                                                int64_t frame, double cell) const {
  std::vector<common::Point> at;
  std::vector<float> shade;
  if (members.empty()) return renderer_->render(at, shade, common::ViewAxis::kRiver);
  const gnn::RolloutResult& first = members.front();
  const auto water = first.active[frame].nonzero().view(-1);
  at = points(first.position[frame].index_select(0, water));
  shade.assign(at.size(), 0.0f);
  std::map<std::pair<int64_t, int64_t>, int> members_with_oil;
  for (const auto& r : members) {
    const auto oil = r.active[frame] & (r.oil_fraction[frame] >= gnn::kOilFractionThreshold);
    const auto c =
        torch::floor(r.position[frame].index({oil}).slice(1, 0, 2).to(torch::kFloat64) / cell)
            .to(torch::kInt64)
            .contiguous();
    std::set<std::pair<int64_t, int64_t>> cells;
    auto a = c.accessor<int64_t, 2>();
    for (int64_t i = 0; i < c.size(0); ++i) cells.insert({a[i][0], a[i][1]});
    for (const auto& key : cells) ++members_with_oil[key];
  }
  for (const auto& [key, count] : members_with_oil) {
    at.emplace_back(float((double(key.first) + 0.5) * cell),
                    float((double(key.second) + 0.5) * cell), top_);
    shade.push_back(float(count) / float(members.size()));
  }
  return renderer_->render(at, shade, common::ViewAxis::kRiver);
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
