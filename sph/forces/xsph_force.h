#pragma once
// XSPH velocity smoothing, Monaghan, "On the problem of penetration in particle methods",
// J. Comput. Phys. 82 (1989): v_i += c sum_j (m_j / rho_ij) (v_j - v_i) W_ij with the pair's
// mean density rho_ij (Monaghan's symmetric form, which conserves momentum), applied as the
// acceleration that produces this change over the coming step.

#include "sph/core/particle_loops.h"
#include "sph/forces/non_pressure_force.h"

namespace sph {

class XsphForce : public NonPressureForce {
 public:
  explicit XsphForce(Real coefficient) : c_(coefficient) {}
  // The scene's top-level `xsph` coefficient turns it on.
  static NonPressureForceEntry entry() {
    return {"xsph",
            {},
            [](const PhysicsContext& physics) { return physics.xsph > 0; },
            [](const PhysicsContext& physics) -> std::unique_ptr<NonPressureForce> {
              return std::make_unique<XsphForce>(physics.xsph);
            }};
  }
  std::string name() const override { return "xsph"; }
  void add_acceleration(FluidParticles& fluid, const BoundaryParticles&,
                        const ParticleNeighbourhood& nb, Real dt) override {
    const Real scale = c_ / dt;
    const Vec3* v = fluid.velocity.data();
    for_each_active(fluid, [&](Index i) {
      Vec3 dv = Vec3::Zero();
      nb.fluid.for_each(i, [&](Index j, Index k) {
        const Real mean_density = fluid.pair_mean_density(i, j);
        dv += (fluid.rest_density[j] * fluid.rest_volume[j] / mean_density * nb.fluid.value[k]) *
              (v[j] - v[i]);
      });
      fluid.acceleration[i] += scale * dv;
    });
  }

 private:
  Real c_;
};

}  // namespace sph
