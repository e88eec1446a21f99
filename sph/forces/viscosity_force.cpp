#include "sph/forces/viscosity_force.h"

#include "sph/core/particle_loops.h"

namespace sph {

NonPressureForceEntry ViscosityForce::entry() {
  return {"viscosity",
          {},
          [](const PhysicsContext& physics) {
            const MaterialsConfig& m = physics.materials;
            return m.water.viscosity > 0 || m.oil.viscosity > 0 || physics.boundary_friction > 0;
          },
          [](const PhysicsContext& physics) -> std::unique_ptr<NonPressureForce> {
            return std::make_unique<ViscosityForce>(physics.boundary_friction);
          }};
}

void ViscosityForce::add_acceleration(FluidParticles& fluid, const BoundaryParticles& boundary,
                                      const ParticleNeighbourhood& nb, Real) {
  const Real h = nb.support_radius();
  const Real eps = Real(0.01) * h * h;
  const Real c = Real(2 * (3 + 2)) * Real(0.5);  // 2 (d + 2) times the 1/2 of the pair mean
  const Real cb = Real(2 * (3 + 2)) * nu_boundary_;
  const Vec3* x = fluid.position.data();
  const Vec3* v = fluid.velocity.data();
  for_each_active(fluid, [&](Index i) {
    Vec3 a = Vec3::Zero();
    {
      nb.fluid.for_each(i, [&](Index j, Index k) {
        const Vec3 xij = x[i] - x[j];
        // m_j / rho_ij with the pair's mean density rho_ij, so that the force on i from j is
        // exactly opposite to the force on j from i (m_i m_j / rho_ij is symmetric) and momentum
        // is conserved also where densities differ (free surface); gradient[k] carries V_j.
        const Real mean_density = fluid.pair_mean_density(i, j);
        const Real nu = fluid.viscosity[i] + fluid.viscosity[j];
        a += (c * nu * fluid.rest_density[j] * (v[i] - v[j]).dot(xij) /
              ((xij.squaredNorm() + eps) * mean_density)) *
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
  });
}

}  // namespace sph
