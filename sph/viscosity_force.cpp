#include "sph/viscosity_force.h"

namespace sph {

void ViscosityForce::add_acceleration(FluidParticles& fluid, const BoundaryParticles& boundary,
                                      const ParticleNeighbourhood& nb, Real) {
  const long n = long(fluid.active_count());
  const Real h = nb.support_radius();
  const Real eps = Real(0.01) * h * h;
  const Real c = Real(2 * (3 + 2)) * nu_;
  const Real cb = Real(2 * (3 + 2)) * nu_boundary_;
  const Vec3* x = fluid.position.data();
  const Vec3* v = fluid.velocity.data();
#pragma omp parallel for schedule(dynamic, 64)
  for (long li = 0; li < n; ++li) {
    const Index i = Index(li);
    Vec3 a = Vec3::Zero();
    if (c > 0) {
      nb.fluid.for_each(i, [&](Index j, Index k) {
        const Vec3 xij = x[i] - x[j];
        // gradient[k] carries V_j; m_j / rho_j = V_j / (rho_j / rho0).
        a += (c * (v[i] - v[j]).dot(xij) / ((xij.squaredNorm() + eps) * fluid.density[j])) *
             nb.fluid.gradient[k];
      });
    }
    if (cb > 0) {
      nb.boundary.for_each(i, [&](Index b, Index k) {
        const Vec3 xib = x[i] - boundary.position[b];
        a += (cb * v[i].dot(xib) / (xib.squaredNorm() + eps)) * nb.boundary.gradient[k];
      });
    }
    fluid.acceleration[i] += a;
  }
}

}  // namespace sph
