#include "farfield/model/centreline.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace farfield {

Centreline::Centreline(std::vector<std::pair<double, double>> points) : points_(std::move(points)) {
  if (points_.size() < 2) throw std::invalid_argument("a centreline needs at least 2 points");
  cumulative_.assign(points_.size(), 0.0);
  for (size_t k = 1; k < points_.size(); ++k) {
    const double d = std::hypot(points_[k].first - points_[k - 1].first,
                                points_[k].second - points_[k - 1].second);
    if (!(d > 0))
      throw std::invalid_argument("centreline point " + std::to_string(k) +
                                  " repeats the one before it");
    cumulative_[k] = cumulative_[k - 1] + d;
  }
  build_index();
}

double Centreline::squared_distance(size_t k, double x, double y, double& s) const {
  const size_t segments = points_.size() - 1;
  const double ax = points_[k].first, ay = points_[k].second;
  const double dx = points_[k + 1].first - ax, dy = points_[k + 1].second - ay;
  const double len = cumulative_[k + 1] - cumulative_[k];
  s = ((x - ax) * dx + (y - ay) * dy) / (len * len);
  // The first and last segments extend beyond the ends, so that a point upstream or
  // downstream of the line still gets a distance along it.
  if (k > 0) s = std::max(s, 0.0);
  if (k + 1 < segments) s = std::min(s, 1.0);
  const double px = ax + s * dx, py = ay + s * dy;
  return (x - px) * (x - px) + (y - py) * (y - py);
}

// Cells about a median segment long, at most 2^14 of them (fewer on a long line), over the line's
// bounding box widened by a tenth of its size. A cell's candidates: the end segments (they reach
// beyond the line's ends) and every segment whose bounding box comes as close to the cell as the
// farthest corner of the cell is from its nearest segment (the distance to a segment is convex, so
// no point of the cell is farther than a corner). That bound errs only outward: the result is a
// plain scan's.
void Centreline::build_index() {
  const size_t segments = points_.size() - 1;
  if (segments < 4) return;  // a plain scan
  double min_x = points_[0].first, max_x = min_x, min_y = points_[0].second, max_y = min_y;
  for (const auto& [x, y] : points_) {
    min_x = std::min(min_x, x);
    max_x = std::max(max_x, x);
    min_y = std::min(min_y, y);
    max_y = std::max(max_y, y);
  }
  const double margin = 0.1 * std::max(max_x - min_x, max_y - min_y);
  min_x -= margin;
  min_y -= margin;
  max_x += margin;
  max_y += margin;
  std::vector<double> lengths(segments);
  for (size_t k = 0; k < segments; ++k) lengths[k] = cumulative_[k + 1] - cumulative_[k];
  std::nth_element(lengths.begin(), lengths.begin() + long(segments / 2), lengths.end());
  const double area = (max_x - min_x) * (max_y - min_y);
  // The building measures every segment from every cell: at most some 4 million of those.
  const double cells = std::min(16384.0, 4e6 / double(segments));
  grid_cell_ = std::max(lengths[segments / 2], std::sqrt(area / cells));
  grid_x0_ = min_x;
  grid_y0_ = min_y;
  grid_nx_ = std::max(1L, long(std::ceil((max_x - min_x) / grid_cell_)));
  grid_ny_ = std::max(1L, long(std::ceil((max_y - min_y) / grid_cell_)));
  cell_start_.assign(size_t(grid_nx_ * grid_ny_) + 1, 0);
  for (long j = 0; j < grid_ny_; ++j)
    for (long i = 0; i < grid_nx_; ++i) {
      const double x0 = grid_x0_ + double(i) * grid_cell_, x1 = x0 + grid_cell_;
      const double y0 = grid_y0_ + double(j) * grid_cell_, y1 = y0 + grid_cell_;
      double bound = std::numeric_limits<double>::infinity();  // squared
      for (size_t k = 0; k < segments; ++k) {
        double s, farthest = 0;
        for (const double cx : {x0, x1})
          for (const double cy : {y0, y1})
            farthest = std::max(farthest, squared_distance(k, cx, cy, s));
        bound = std::min(bound, farthest);
      }
      const double root = std::sqrt(bound) * (1 + 1e-9) + 1e-3;  // rounding's margin
      for (size_t k = 0; k < segments; ++k) {
        const auto [ax, ay] = points_[k];
        const auto [bx, by] = points_[k + 1];
        const double gx = std::max({std::min(ax, bx) - x1, 0.0, x0 - std::max(ax, bx)});
        const double gy = std::max({std::min(ay, by) - y1, 0.0, y0 - std::max(ay, by)});
        if (k == 0 || k + 1 == segments || gx * gx + gy * gy <= root * root)
          cell_segments_.push_back(k);
      }
      cell_start_[size_t(j * grid_nx_ + i) + 1] = cell_segments_.size();
    }
}

RiverPosition Centreline::nearest(const size_t* candidates, size_t count, double x,
                                  double y) const {
  const auto segment = [&](size_t c) { return candidates ? candidates[c] : c; };
  size_t best = segment(0);
  double best_s;
  double best_squared = squared_distance(best, x, y, best_s);
  for (size_t c = 1; c < count; ++c) {
    double s;
    const double squared = squared_distance(segment(c), x, y, s);
    if (squared < best_squared) {
      best_squared = squared;
      best = segment(c);
      best_s = s;
    }
  }
  const double ax = points_[best].first, ay = points_[best].second;
  const double dx = points_[best + 1].first - ax, dy = points_[best + 1].second - ay;
  RiverPosition p;
  p.along_m = cumulative_[best] + best_s * (cumulative_[best + 1] - cumulative_[best]);
  // The cross product of the direction and the point: positive to the left.
  const double distance = std::sqrt(best_squared);
  p.offset_m = dx * (y - ay) - dy * (x - ax) >= 0 ? distance : -distance;
  return p;
}

// The segments are compared by squared distance and only the nearest is rooted: glibc's hypot,
// careful of overflow, took 44 % of a forecast's time on a real reach, where every step
// locates the elements that meet a bank. Within the grid only a cell's candidates are measured.
RiverPosition Centreline::locate(double x, double y) const {
  const double fx = (x - grid_x0_) / grid_cell_, fy = (y - grid_y0_) / grid_cell_;
  if (fx >= 0 && fy >= 0 && fx < double(grid_nx_) && fy < double(grid_ny_)) {
    const size_t c = size_t(long(fy) * grid_nx_ + long(fx));
    return nearest(cell_segments_.data() + cell_start_[c], cell_start_[c + 1] - cell_start_[c], x,
                   y);
  }
  return nearest(nullptr, points_.size() - 1, x, y);
}

void Centreline::point_at(double along, double offset, double& x, double& y) const {
  size_t k = 0;
  while (k + 2 < points_.size() && cumulative_[k + 1] < along) ++k;
  const double len = cumulative_[k + 1] - cumulative_[k];
  const double ex = (points_[k + 1].first - points_[k].first) / len;
  const double ey = (points_[k + 1].second - points_[k].second) / len;
  const double s = along - cumulative_[k];
  x = points_[k].first + s * ex - offset * ey;
  y = points_[k].second + s * ey + offset * ex;
}

}  // namespace farfield
