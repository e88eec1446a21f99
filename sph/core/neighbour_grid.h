#pragma once
// Fixed-radius neighbour search on a uniform grid (cell size = search radius) over a bounded
// domain. Points are sorted into cells by a counting sort; a query scans the 3 x 3 x 3 block of
// cells around it, where the three cells of each x-row are one contiguous range of the sorted
// order. Results are CSR lists (offsets, indices), filled in parallel with OpenMP: chunks of
// queries collect their neighbours separately, then the pieces are concatenated in order.

#include <cstdint>
#include <stdexcept>
#include <vector>

#include "sph/core/neighbour_row_scan.h"
#include "sph/core/types.h"

namespace sph {

// Neighbour lists in compressed sparse row form: the neighbours of query i are
// indices[offsets[i] .. offsets[i + 1]).
struct NeighbourLists {
  std::vector<Index> offsets;  // [queries + 1]
  std::vector<Index> indices;  // [pairs]

  Index queries() const { return offsets.empty() ? 0 : static_cast<Index>(offsets.size() - 1); }
  Index count(Index i) const { return offsets[i + 1] - offsets[i]; }
  Index pairs() const { return offsets.empty() ? 0 : offsets.back(); }

  template <class F>
  void for_each(Index i, F&& f) const {
    for (Index k = offsets[i]; k < offsets[i + 1]; ++k) f(indices[k]);
  }
};

// Thrown by NeighbourGrid::build when a point lies outside the domain; carries its index.
class PointOutsideDomain : public std::runtime_error {
 public:
  PointOutsideDomain(Index index, const Vec3& p)
      : std::runtime_error("point outside the domain"), index_(index), point_(p) {}
  Index index() const { return index_; }
  const Vec3& point() const { return point_; }

 private:
  Index index_;
  Vec3 point_;
};

class NeighbourGrid {
 public:
  NeighbourGrid() = default;
  // `domain` bounds every point that will be built; `radius` is the search radius.
  NeighbourGrid(const Aabb& domain, Real radius);

  Real radius() const { return radius_; }
  const Aabb& domain() const { return domain_; }

  // Sorts points[0 .. count) into cells. Throws PointOutsideDomain (or on NaN).
  void build(const Vec3* points, Index count);
  void build(const std::vector<Vec3>& points) { build(points.data(), Index(points.size())); }

  // Neighbours within the radius (|x_q - x_p| < radius) among the built points, for each query.
  // With `same_set` the queries are the built points themselves and a point is not its own
  // neighbour. Indices refer to the order the points were given to build().
  void find(const Vec3* queries, Index count, bool same_set, NeighbourLists& out);

  // Uses this version of the innermost scan instead of the fastest the CPU offers (tests).
  void use_row_scan(RowScan scan) { scan_ = scan; }

  // Built point indices sorted by cell (x fastest): a permutation that gives memory locality.
  const std::vector<Index>& cell_order() const { return sorted_index_; }

  // Calls f(j) for every built point j within the radius of x.
  template <class F>
  void for_each_near(const Vec3& x, F&& f) const;

 private:
  // Cell index of p, or -1 when p lies outside the domain (or is NaN).
  std::int64_t cell_of(const Vec3& p) const;

  Aabb domain_;
  Real radius_ = 0;
  Real cell_ = 0;
  Real inv_cell_ = 0;
  std::int64_t nx_ = 0, ny_ = 0, nz_ = 0;
  std::vector<Index> cell_start_;                     // [cells + 1]
  std::vector<Index> sorted_index_;                   // built points by cell
  std::vector<Real> sorted_x_, sorted_y_, sorted_z_;  // their coordinates, for contiguous scans
  std::vector<Index> point_cell_;                     // scratch: cell of each built point
  std::vector<Index> cell_fill_;  // scratch: next free slot of each cell in the counting sort
  std::vector<std::vector<Index>> chunk_buffers_;  // reused across calls
  std::vector<size_t> chunk_used_;
  RowScan scan_ = available_row_scans().back().scan;
};

template <class F>
void NeighbourGrid::for_each_near(const Vec3& x, F&& f) const {
  const Real r2 = radius_ * radius_;
  const Vec3 rel = (x - domain_.min) * inv_cell_;
  const std::int64_t cx =
      std::min<std::int64_t>(std::max<std::int64_t>(std::int64_t(rel[0]), 0), nx_ - 1);
  const std::int64_t cy =
      std::min<std::int64_t>(std::max<std::int64_t>(std::int64_t(rel[1]), 0), ny_ - 1);
  const std::int64_t cz =
      std::min<std::int64_t>(std::max<std::int64_t>(std::int64_t(rel[2]), 0), nz_ - 1);
  const std::int64_t x0 = std::max<std::int64_t>(cx - 1, 0),
                     x1 = std::min<std::int64_t>(cx + 1, nx_ - 1);
  for (std::int64_t z = std::max<std::int64_t>(cz - 1, 0);
       z <= std::min<std::int64_t>(cz + 1, nz_ - 1); ++z)
    for (std::int64_t y = std::max<std::int64_t>(cy - 1, 0);
         y <= std::min<std::int64_t>(cy + 1, ny_ - 1); ++y) {
      const std::int64_t row = (z * ny_ + y) * nx_;
      const Index begin = cell_start_[row + x0], end = cell_start_[row + x1 + 1];
      for (Index k = begin; k < end; ++k) {
        const Real dx = sorted_x_[k] - x[0], dy = sorted_y_[k] - x[1], dz = sorted_z_[k] - x[2];
        if (dx * dx + dy * dy + dz * dz < r2) f(sorted_index_[k]);
      }
    }
}

}  // namespace sph
