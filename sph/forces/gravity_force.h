#pragma once
// Uniform gravity.

#include "sph/core/particle_loops.h"
#include "sph/forces/non_pressure_force.h"

namespace sph {

class GravityForce : public NonPressureForce {
 public:
  explicit GravityForce(const Vec3& g) : g_(g) {}
  static NonPressureForceEntry entry() {
    return {"gravity",
            {},
            [](const PhysicsContext&) { return true; },
            [](const PhysicsContext& physics) -> std::unique_ptr<NonPressureForce> {
              return std::make_unique<GravityForce>(physics.gravity);
            }};
  }
  std::string name() const override { return "gravity"; }
  void add_acceleration(FluidParticles& fluid, const BoundaryParticles&,
                        const ParticleNeighbourhood&, Real) override {
    for_each_active(
        fluid, [&](Index i) { fluid.acceleration[i] += g_; }, Schedule::kStatic);
  }

 private:
  Vec3 g_;
};

}  // namespace sph
