#include "sph/surface_tension_force.h"

#include <cmath>

namespace sph {

namespace {

constexpr Real kPi = Real(3.14159265358979323846);

// Neighbours of a particle inside a cubic lattice of `spacing` within `radius` (itself excluded).
Index full_neighbour_count(Real spacing, Real radius) {
  const int reach = int(std::ceil(radius / spacing));
  Index count = 0;
  for (int x = -reach; x <= reach; ++x)
    for (int y = -reach; y <= reach; ++y)
      for (int z = -reach; z <= reach; ++z) {
        const Real r2 = spacing * spacing * Real(x * x + y * y + z * z);
        if (r2 > 0 && r2 < radius * radius) ++count;
      }
  return count;
}

// cos(3 pi q / 2) for q = r / h in [0, 1]: with t = 3 pi q / 2 - pi, cos(t + pi) = -cos(t) and
// |t| <= pi; a Taylor polynomial of cos to t^12 is within 1e-4 there, far below the force's own
// accuracy, and several times cheaper than std::cos in the pair loop.
inline Real cosine_law(Real q) {
  const Real t = Real(1.5) * kPi * q - kPi;
  const Real t2 = t * t;
  const Real c =
      1 + t2 * (Real(-1. / 2) +
                t2 * (Real(1. / 24) +
                      t2 * (Real(-1. / 720) +
                            t2 * (Real(1. / 40320) +
                                  t2 * (Real(-1. / 3628800) + t2 * Real(1. / 479001600))))));
  return -c;
}

}  // namespace

SurfaceTensionForce::SurfaceTensionForce(const SurfaceTensionConfig& config, Real particle_spacing,
                                         Real support_radius, Real reference_density)
    : config_(config),
      reference_density_(reference_density),
      surface_neighbour_count_(
          Index(config.surface_neighbour_fraction *
                Real(full_neighbour_count(particle_spacing, support_radius)))) {}

void SurfaceTensionForce::add_acceleration(FluidParticles& fluid, const BoundaryParticles& boundary,
                                           const ParticleNeighbourhood& nb, Real) {
  const long n = long(fluid.active_count());
  const Real h = nb.support_radius();
  const Real inv_h = 1 / h;
  const Vec3* x = fluid.position.data();
  const ParticleType* type = fluid.type.data();
  const Real s_like = config_.like, s_unlike = config_.unlike, s_wall = config_.boundary;
#pragma omp parallel for schedule(dynamic, 64)
  for (long li = 0; li < n; ++li) {
    const Index i = Index(li);
    const auto& ff = nb.fluid;
    const Index begin = ff.lists.offsets[i], end = ff.lists.offsets[i + 1];
    if (config_.surface_only) {
      bool acts = end - begin + nb.boundary.lists.count(i) < surface_neighbour_count_;
      for (Index k = begin; k < end && !acts; ++k) acts = type[ff.lists.indices[k]] != type[i];
      if (!acts) continue;
    }
    Vec3 a = Vec3::Zero();
    for (Index k = begin; k < end; ++k) {
      const Index j = ff.lists.indices[k];
      const Vec3 xij = x[i] - x[j];
      const Real r = xij.norm();
      if (r <= 0) continue;
      const Real s = type[j] == type[i] ? s_like : s_unlike;
      a += (s * fluid.rest_volume[j] * cosine_law(r * inv_h) * ff.value[k] / r) * xij;
    }
    if (s_wall != 0) {
      nb.boundary.for_each(i, [&](Index b, Index k) {
        const Vec3 xib = x[i] - boundary.position[b];
        const Real r = xib.norm();
        if (r > 0)
          a += (s_wall * boundary.volume[b] * cosine_law(r * inv_h) * nb.boundary.value[k] / r) *
               xib;
      });
    }
    fluid.acceleration[i] += (reference_density_ / fluid.rest_density[i]) * a;
  }
}

}  // namespace sph
