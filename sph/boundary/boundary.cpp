#include "sph/boundary/boundary.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include "sph/core/lattice.h"
#include "sph/core/neighbour_grid.h"

namespace sph {

namespace {

int divisions(Real length, Real spacing) {
  return std::max(1, int(std::ceil(length / spacing - Real(1e-4))));
}

// Removes points closer than `tolerance` to an earlier point (shared edges of faces, overlapping
// surfaces), keeping the first; uses a hash of rounded coordinates.
std::vector<Vec3> remove_duplicates(const std::vector<Vec3>& points, Real tolerance) {
  std::map<std::tuple<long, long, long>, int> seen;
  std::vector<Vec3> out;
  out.reserve(points.size());
  for (const auto& p : points) {
    const auto key = std::make_tuple(std::lround(p[0] / tolerance), std::lround(p[1] / tolerance),
                                     std::lround(p[2] / tolerance));
    if (seen.emplace(key, 1).second) out.push_back(p);
  }
  return out;
}

}  // namespace

std::vector<Vec3> sample_box_surface(const Vec3& lo, const Vec3& hi, Real spacing, bool open_top) {
  std::vector<Vec3> points;
  const Vec3 size = hi - lo;
  const int n[3] = {divisions(size[0], spacing), divisions(size[1], spacing),
                    divisions(size[2], spacing)};
  // Each face is the set of lattice nodes with one coordinate fixed at its min or max.
  for (int axis = 0; axis < 3; ++axis) {
    const int a = (axis + 1) % 3, b = (axis + 2) % 3;
    for (int side = 0; side < 2; ++side) {
      if (open_top && axis == 2 && side == 1) continue;
      for (int i = 0; i <= n[a]; ++i)
        for (int j = 0; j <= n[b]; ++j) {
          Vec3 p;
          p[axis] = side ? hi[axis] : lo[axis];
          p[a] = lo[a] + size[a] * Real(i) / Real(n[a]);
          p[b] = lo[b] + size[b] * Real(j) / Real(n[b]);
          points.push_back(p);
        }
    }
  }
  return remove_duplicates(points, spacing * Real(0.25));
}

std::vector<Vec3> sample_height_field(const HeightFieldConfig& field, Real spacing) {
  const int gx = int(field.heights[0].size()), gy = int(field.heights.size());
  const Real cell = field.cell_size;
  auto height_at = [&](Real x, Real y) {
    const Real fx = std::clamp((x - field.origin[0]) / cell, Real(0), Real(gx - 1));
    const Real fy = std::clamp((y - field.origin[1]) / cell, Real(0), Real(gy - 1));
    const int ix = std::min(int(fx), gx - 2), iy = std::min(int(fy), gy - 2);
    const Real tx = fx - Real(ix), ty = fy - Real(iy);
    const auto& h = field.heights;
    return (1 - tx) * (1 - ty) * h[iy][ix] + tx * (1 - ty) * h[iy][ix + 1] +
           (1 - tx) * ty * h[iy + 1][ix] + tx * ty * h[iy + 1][ix + 1];
  };
  const Real lx = cell * Real(gx - 1), ly = cell * Real(gy - 1);
  const int nx = divisions(lx, spacing), ny = divisions(ly, spacing);
  std::vector<Real> z(size_t((nx + 1) * (ny + 1)));
  auto at = [&](int i, int j) -> Real& { return z[size_t(j * (nx + 1) + i)]; };
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i)
      at(i, j) = height_at(field.origin[0] + lx * Real(i) / Real(nx),
                           field.origin[1] + ly * Real(j) / Real(ny));
  std::vector<Vec3> points;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      const Real x = field.origin[0] + lx * Real(i) / Real(nx);
      const Real y = field.origin[1] + ly * Real(j) / Real(ny);
      const Real zi = at(i, j);
      points.emplace_back(x, y, zi);
      // Fill down to the lowest direct neighbour so steep slopes have no holes.
      Real lowest = zi;
      if (i > 0) lowest = std::min(lowest, at(i - 1, j));
      if (i < nx) lowest = std::min(lowest, at(i + 1, j));
      if (j > 0) lowest = std::min(lowest, at(i, j - 1));
      if (j < ny) lowest = std::min(lowest, at(i, j + 1));
      const int fill = int(std::floor((zi - lowest) / spacing));
      for (int k = 1; k <= fill; ++k) points.emplace_back(x, y, zi - Real(k) * spacing);
    }
  return points;
}

std::vector<Real> boundary_volumes(const std::vector<Vec3>& positions, KernelKind kernel,
                                   Real support_radius) {
  std::vector<Real> volume(positions.size(), 0);
  if (positions.empty()) return volume;
  Aabb box{positions[0], positions[0]};
  for (const auto& p : positions) {
    box.min = box.min.cwiseMin(p);
    box.max = box.max.cwiseMax(p);
  }
  box.min.array() -= support_radius;
  box.max.array() += support_radius;
  NeighbourGrid grid(box, support_radius);
  grid.build(positions);
  with_kernel(kernel, support_radius, [&](const auto& w) {
#pragma omp parallel for schedule(static)
    for (long b = 0; b < long(positions.size()); ++b) {
      Real sum = 0;  // includes b itself (r = 0)
      grid.for_each_near(positions[size_t(b)],
                         [&](Index k) { sum += w.value(positions[size_t(b)] - positions[k]); });
      volume[size_t(b)] = Real(1) / sum;
    }
    return 0;
  });
  return volume;
}

BoundaryParticles build_boundary(const std::vector<BoxConfig>& boxes,
                                 const std::vector<HeightFieldConfig>& height_fields, Real spacing,
                                 Real support_radius, KernelKind kernel) {
  // The boundary layer sits behind each declared surface, at the distance where a fluid lattice
  // resting against the surface (centres one radius in front of it) has the rest density: about
  // 1.3 radii for the cubic spline with a 4-radius support. A layer on the surface itself would
  // give 1.55 rho0 at one radius, and the first pressure solve would blow such a block apart.
  const Real offset = boundary_layer_offset(kernel, support_radius, spacing);
  std::vector<Vec3> points;
  for (const auto& box : boxes) {
    Vec3 lo = box.min, hi = box.max;
    if (box.fluid_side == "inside") {
      lo.array() -= offset;
      hi.array() += offset;
    } else {
      const Vec3 centre = Real(0.5) * (lo + hi);
      lo = (lo.array() + offset).cwiseMin(centre.array());
      hi = (hi.array() - offset).cwiseMax(centre.array());
    }
    auto p = sample_box_surface(lo, hi, spacing, box.open_top);
    points.insert(points.end(), p.begin(), p.end());
  }
  for (const auto& field : height_fields) {
    HeightFieldConfig lowered = field;
    for (auto& row : lowered.heights)
      for (auto& z : row) z -= offset;
    auto p = sample_height_field(lowered, spacing);
    points.insert(points.end(), p.begin(), p.end());
  }
  BoundaryParticles boundary;
  boundary.position = remove_duplicates(points, spacing * Real(0.25));
  boundary.volume = boundary_volumes(boundary.position, kernel, support_radius);
  return boundary;
}

}  // namespace sph
