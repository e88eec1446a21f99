#include "sph/solvers/pfsph_solver.h"

#include <chrono>
#include <cmath>

#include "common/stopwatch.h"
#include "sph/core/particle_loops.h"

namespace sph {

PressureSolverEntry PfsphSolver::entry() {
  return {"pfsph",
          // It reads WCSPH's settings (registered by WCSPH) and owns the pair strengths.
          {common::ConfigSectionEntry::of<PfsphConfig>(
              "pfsph", "PF-SPH pairwise-force strengths (solver pfsph only)")},
          {},
          [](const PhysicsContext& physics) -> std::unique_ptr<PressureSolver> {
            return std::make_unique<PfsphSolver>(physics);
          }};
}

PfsphSolver::PfsphSolver(const PhysicsContext& physics)
    : WcsphSolver(physics.settings<WcsphConfig>("wcsph"), physics.particle_diameter(),
                  physics.time_step.cfl, physics.materials.water.density),
      config_(physics.settings<PfsphConfig>("pfsph")) {}

void PfsphSolver::after_non_pressure_forces(SolverHost& host, Real) {
  common::ScopedTimer timer(host.time_split().solver_parts["pairwise_force"]);
  FluidParticles& fluid = host.mutable_fluid();
  const ParticleNeighbourhood& nb = host.neighbourhood();
  const BoundaryParticles& boundary = host.boundary();
  const Real h = nb.support_radius();
  const Real wave = Real(3 * M_PI / 2) / h;
  const Real strength[2][2] = {{config_.water_water, config_.oil_water},
                               {config_.oil_water, config_.oil_oil}};
  const bool walls = config_.boundary != 0;
  const Vec3* x = fluid.position.data();
  auto pair_force = [&](const Vec3& d) -> Vec3 {
    const Real r = d.norm();
    if (r <= Real(1e-9) * h || r >= h) return Vec3::Zero();
    return (std::cos(wave * r) / r) * d;
  };
  for_each_active(fluid, [&](Index i) {
    const int phase_i = is_oil(fluid.oil_fraction[i]);
    Vec3 a = Vec3::Zero();
    nb.fluid.for_each(i, [&](Index j, Index) {
      const int phase_j = is_oil(fluid.oil_fraction[j]);
      a += strength[phase_i][phase_j] * pair_force(x[i] - x[j]);
    });
    if (walls)
      nb.boundary.for_each(i, [&](Index b, Index) {
        a += config_.boundary * pair_force(x[i] - boundary.position[b]);
      });
    fluid.acceleration[i] += (reference_density() / fluid.rest_density[i]) * a;
  });
}

}  // namespace sph
