#include "sph/neighbour_grid.h"

#include <omp.h>

#include <algorithm>
#include <cmath>

namespace sph {

NeighbourGrid::NeighbourGrid(const Aabb& domain, Real radius)
    : domain_(domain), radius_(radius), inv_cell_(Real(1) / radius) {
  const Vec3 extent = domain.max - domain.min;
  nx_ = std::max<std::int64_t>(1, std::int64_t(std::ceil(extent[0] * inv_cell_)));
  ny_ = std::max<std::int64_t>(1, std::int64_t(std::ceil(extent[1] * inv_cell_)));
  nz_ = std::max<std::int64_t>(1, std::int64_t(std::ceil(extent[2] * inv_cell_)));
  if (nx_ * ny_ * nz_ > (std::int64_t(1) << 31))
    throw std::invalid_argument("neighbour grid: the domain has too many cells for this radius");
  cell_start_.assign(size_t(nx_ * ny_ * nz_ + 1), 0);
}

std::int64_t NeighbourGrid::cell_of(const Vec3& p, bool clamp) const {
  const Vec3 rel = (p - domain_.min) * inv_cell_;
  std::int64_t c[3];
  const std::int64_t n[3] = {nx_, ny_, nz_};
  for (int k = 0; k < 3; ++k) {
    // NaN compares false, so it is caught here as well.
    if (!(rel[k] >= 0 && rel[k] <= Real(n[k]))) {
      if (!clamp) return -1;
      c[k] = rel[k] > 0 ? n[k] - 1 : 0;
    } else {
      c[k] = std::min<std::int64_t>(std::int64_t(rel[k]), n[k] - 1);
    }
  }
  return (c[2] * ny_ + c[1]) * nx_ + c[0];
}

void NeighbourGrid::build(const Vec3* points, Index count) {
  const size_t cells = cell_start_.size() - 1;
  point_cell_.resize(count);
  std::fill(cell_start_.begin(), cell_start_.end(), 0);
  for (Index i = 0; i < count; ++i) {
    const std::int64_t c = cell_of(points[i], false);
    if (c < 0) throw PointOutsideDomain(i, points[i]);
    point_cell_[i] = Index(c);
    ++cell_start_[size_t(c) + 1];
  }
  for (size_t c = 0; c < cells; ++c) cell_start_[c + 1] += cell_start_[c];
  sorted_index_.resize(count);
  sorted_point_.resize(count);
  // Counting sort; stable, so the result is deterministic.
  std::vector<Index> fill(cell_start_.begin(), cell_start_.end() - 1);
  for (Index i = 0; i < count; ++i) {
    const Index slot = fill[point_cell_[i]]++;
    sorted_index_[slot] = i;
    sorted_point_[slot] = points[i];
  }
}

void NeighbourGrid::find(const Vec3* queries, Index count, bool same_set, NeighbourLists& out) {
  out.offsets.resize(size_t(count) + 1);
  out.offsets[0] = 0;
  const Real r2 = radius_ * radius_;
  thread_buffers_.resize(size_t(omp_get_max_threads()));
#pragma omp parallel
  {
    const int t = omp_get_thread_num();
    const int nt = omp_get_num_threads();
    const Index begin = Index(std::uint64_t(count) * t / nt);
    const Index end = Index(std::uint64_t(count) * (t + 1) / nt);
    std::vector<Index>& buffer = thread_buffers_[size_t(t)];
    buffer.clear();
    for (Index i = begin; i < end; ++i) {
      const Vec3 x = queries[i];
      const Vec3 rel = (x - domain_.min) * inv_cell_;
      const std::int64_t cx = std::min<std::int64_t>(std::max<std::int64_t>(std::int64_t(rel[0]), 0), nx_ - 1);
      const std::int64_t cy = std::min<std::int64_t>(std::max<std::int64_t>(std::int64_t(rel[1]), 0), ny_ - 1);
      const std::int64_t cz = std::min<std::int64_t>(std::max<std::int64_t>(std::int64_t(rel[2]), 0), nz_ - 1);
      const std::int64_t x0 = std::max<std::int64_t>(cx - 1, 0);
      const std::int64_t x1 = std::min<std::int64_t>(cx + 1, nx_ - 1);
      const size_t before = buffer.size();
      for (std::int64_t z = std::max<std::int64_t>(cz - 1, 0); z <= std::min<std::int64_t>(cz + 1, nz_ - 1); ++z) {
        for (std::int64_t y = std::max<std::int64_t>(cy - 1, 0); y <= std::min<std::int64_t>(cy + 1, ny_ - 1); ++y) {
          const std::int64_t row = (z * ny_ + y) * nx_;
          const Index cbegin = cell_start_[size_t(row + x0)];
          const Index cend = cell_start_[size_t(row + x1 + 1)];
          for (Index k = cbegin; k < cend; ++k) {
            if ((sorted_point_[k] - x).squaredNorm() < r2) {
              const Index j = sorted_index_[k];
              if (!same_set || j != i) buffer.push_back(j);
            }
          }
        }
      }
      out.offsets[size_t(i) + 1] = Index(buffer.size() - before);
    }
#pragma omp barrier
#pragma omp single
    {
      for (Index i = 0; i < count; ++i) out.offsets[size_t(i) + 1] += out.offsets[i];
      out.indices.resize(out.offsets[count]);
    }
    std::copy(buffer.begin(), buffer.end(), out.indices.begin() + out.offsets[begin]);
  }
}

}  // namespace sph
