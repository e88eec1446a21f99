#include "sph/core/neighbour_grid.h"

#include <omp.h>

#include <algorithm>
#include <cmath>

namespace sph {

NeighbourGrid::NeighbourGrid(const Aabb& domain, Real radius)
    : domain_(domain), radius_(radius), cell_(radius), inv_cell_(Real(1) / radius) {
  const Vec3 extent = domain.max - domain.min;
  nx_ = std::max<std::int64_t>(1, std::int64_t(std::ceil(extent[0] * inv_cell_)));
  ny_ = std::max<std::int64_t>(1, std::int64_t(std::ceil(extent[1] * inv_cell_)));
  nz_ = std::max<std::int64_t>(1, std::int64_t(std::ceil(extent[2] * inv_cell_)));
  if (nx_ * ny_ * nz_ > (std::int64_t(1) << 31))
    throw std::invalid_argument("neighbour grid: the domain has too many cells for this radius");
  cell_start_.assign(size_t(nx_ * ny_ * nz_ + 1), 0);
}

std::int64_t NeighbourGrid::cell_of(const Vec3& p) const {
  const Vec3 rel = (p - domain_.min) * inv_cell_;
  std::int64_t c[3];
  const std::int64_t n[3] = {nx_, ny_, nz_};
  for (int k = 0; k < 3; ++k) {
    // NaN compares false, so it is caught here as well.
    if (!(rel[k] >= 0 && rel[k] <= Real(n[k]))) return -1;
    c[k] = std::min<std::int64_t>(std::int64_t(rel[k]), n[k] - 1);
  }
  return (c[2] * ny_ + c[1]) * nx_ + c[0];
}

void NeighbourGrid::build(const Vec3* points, Index count) {
  const size_t cells = cell_start_.size() - 1;
  point_cell_.resize(count);
  std::fill(cell_start_.begin(), cell_start_.end(), 0);
  for (Index i = 0; i < count; ++i) {
    const std::int64_t c = cell_of(points[i]);
    if (c < 0) throw PointOutsideDomain(i, points[i]);
    point_cell_[i] = Index(c);
    ++cell_start_[size_t(c) + 1];
  }
  for (size_t c = 0; c < cells; ++c) cell_start_[c + 1] += cell_start_[c];
  sorted_index_.resize(count);
  sorted_x_.resize(count);
  sorted_y_.resize(count);
  sorted_z_.resize(count);
  // Counting sort; stable, so the result is deterministic.
  cell_fill_.assign(cell_start_.begin(), cell_start_.end() - 1);
  for (Index i = 0; i < count; ++i) {
    const Index slot = cell_fill_[point_cell_[i]]++;
    sorted_index_[slot] = i;
    sorted_x_[slot] = points[i][0];
    sorted_y_[slot] = points[i][1];
    sorted_z_[slot] = points[i][2];
  }
}

void NeighbourGrid::find(const Vec3* queries, Index count, bool same_set, NeighbourLists& out) {
  out.offsets.resize(size_t(count) + 1);
  out.offsets[0] = 0;
  const Real r2 = radius_ * radius_;
  // Queries are processed in chunks handed out dynamically: neighbour counts vary a lot across
  // the domain (a dense pool below, spray above), so equal static ranges leave a thread idle.
  // Each chunk collects its neighbours in its own buffer; the buffers are concatenated in order,
  // so the result does not depend on the thread count.
  constexpr Index kChunk = 128;
  const SortedPoints points{sorted_x_.data(), sorted_y_.data(), sorted_z_.data(),
                            sorted_index_.data()};
  const Index chunks = (count + kChunk - 1) / kChunk;
  if (chunk_buffers_.size() < chunks) chunk_buffers_.resize(chunks);
  chunk_used_.assign(chunks, 0);
#pragma omp parallel
  {
#pragma omp for schedule(dynamic, 1)
    for (long c = 0; c < long(chunks); ++c) {
      std::vector<Index>& buffer = chunk_buffers_[size_t(c)];
      size_t used = 0;
      const Index begin = Index(c) * kChunk, end = std::min(count, begin + kChunk);
      for (Index i = begin; i < end; ++i) {
        const Vec3 x = queries[i];
        const Vec3 rel = (x - domain_.min) * inv_cell_;
        const std::int64_t cx = std::clamp<std::int64_t>(std::int64_t(rel[0]), 0, nx_ - 1);
        const std::int64_t cy = std::clamp<std::int64_t>(std::int64_t(rel[1]), 0, ny_ - 1);
        const std::int64_t cz = std::clamp<std::int64_t>(std::int64_t(rel[2]), 0, nz_ - 1);
        const std::int64_t x0 = std::max<std::int64_t>(cx - 1, 0);
        const std::int64_t x1 = std::min<std::int64_t>(cx + 1, nx_ - 1);
        const size_t before = used;
        // Distance from the query to the lower and upper faces of its own cell, per axis: a row
        // of cells one step off in y and z starts that far away, so corner rows that lie
        // entirely beyond the radius are skipped without scanning their particles.
        const Real fy = rel[1] - Real(cy), fz = rel[2] - Real(cz);
        const Real gap_y[3] = {fy * cell_, 0, (Real(1) - fy) * cell_};
        const Real gap_z[3] = {fz * cell_, 0, (Real(1) - fz) * cell_};
        const Real query[3] = {x[0], x[1], x[2]};
        const Index self = same_set ? i : ~Index(0);
        for (std::int64_t z = std::max<std::int64_t>(cz - 1, 0);
             z <= std::min<std::int64_t>(cz + 1, nz_ - 1); ++z) {
          const Real gz = gap_z[z - cz + 1];
          for (std::int64_t y = std::max<std::int64_t>(cy - 1, 0);
               y <= std::min<std::int64_t>(cy + 1, ny_ - 1); ++y) {
            const Real gy = gap_y[y - cy + 1];
            if (gy * gy + gz * gz >= r2) continue;
            const std::int64_t row = (z * ny_ + y) * nx_;
            const Index cbegin = cell_start_[size_t(row + x0)];
            const Index cend = cell_start_[size_t(row + x1 + 1)];
            const size_t room = used + (cend - cbegin) + kRowScanSlack;
            if (buffer.size() < room) buffer.resize(2 * room);
            const size_t n = scan_(points, cbegin, cend, query, r2, self, buffer.data() + used);
            used += n;
          }
        }
        out.offsets[size_t(i) + 1] = Index(used - before);
      }
      chunk_used_[size_t(c)] = used;
    }
#pragma omp single
    {
      for (Index i = 0; i < count; ++i) out.offsets[size_t(i) + 1] += out.offsets[i];
      out.indices.resize(out.offsets[count]);
    }
#pragma omp for schedule(dynamic, 4)
    for (long c = 0; c < long(chunks); ++c) {
      const std::vector<Index>& buffer = chunk_buffers_[size_t(c)];
      std::copy(buffer.begin(), buffer.begin() + std::ptrdiff_t(chunk_used_[size_t(c)]),
                out.indices.begin() + out.offsets[size_t(c) * kChunk]);
    }
  }
}

}  // namespace sph
