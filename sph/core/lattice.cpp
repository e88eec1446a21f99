#include "sph/core/lattice.h"

#include <algorithm>
#include <cmath>

namespace sph {

std::vector<Vec3> lattice_points(const Vec3& lo, const Vec3& hi, Real spacing) {
  std::vector<Vec3> points;
  const Real half = Real(0.5) * spacing;
  int n[3];
  for (int k = 0; k < 3; ++k)
    n[k] = std::max(0, int(std::floor((hi[k] - lo[k]) / spacing + Real(1e-4))));
  for (int iz = 0; iz < n[2]; ++iz)
    for (int iy = 0; iy < n[1]; ++iy)
      for (int ix = 0; ix < n[0]; ++ix)
        points.emplace_back(lo[0] + half + Real(ix) * spacing, lo[1] + half + Real(iy) * spacing,
                            lo[2] + half + Real(iz) * spacing);
  return points;
}

Real lattice_rest_volume(KernelKind kernel, Real support_radius, Real spacing) {
  const int reach = int(std::ceil(support_radius / spacing));
  return with_kernel(kernel, support_radius, [&](const auto& w) {
    double sum = 0;
    for (int i = -reach; i <= reach; ++i)
      for (int j = -reach; j <= reach; ++j)
        for (int k = -reach; k <= reach; ++k)
          sum += double(w.value(Vec3(Real(i) * spacing, Real(j) * spacing, Real(k) * spacing)));
    return Real(1.0 / sum);
  });
}

Real boundary_layer_offset(KernelKind kernel, Real support_radius, Real spacing) {
  const int reach = int(std::ceil(support_radius / spacing)) + 1;
  const double volume = double(lattice_rest_volume(kernel, support_radius, spacing));
  return with_kernel(kernel, support_radius, [&](const auto& w) {
    // Sum of W over a square lattice plane at height z below/above the particle.
    auto plane_sum = [&](double z) {
      double sum = 0;
      for (int i = -reach; i <= reach; ++i)
        for (int j = -reach; j <= reach; ++j)
          sum += double(w.value(Vec3(Real(i) * spacing, Real(j) * spacing, Real(z))));
      return sum;
    };
    const double boundary_volume = 1.0 / plane_sum(0);
    double fluid = 0;  // first-layer particle: its own half-space of fluid layers
    for (int layer = 0; layer <= reach; ++layer)
      fluid += volume * plane_sum(layer * double(spacing));
    const double half = 0.5 * double(spacing);
    // Density of the first layer with the boundary plane `offset` behind the surface; it falls
    // with the offset, so bisect for 1.
    auto density = [&](double offset) {
      return fluid + boundary_volume * plane_sum(half + offset);
    };
    double lo = 0, hi = double(support_radius);
    if (density(lo) <= 1) return Real(0);
    for (int it = 0; it < 60; ++it) {
      const double mid = 0.5 * (lo + hi);
      (density(mid) > 1 ? lo : hi) = mid;
    }
    return Real(0.5 * (lo + hi));
  });
}

}  // namespace sph
