#include "sph/solvers/wcsph_solver.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "common/stopwatch.h"
#include "sph/core/particle_loops.h"

namespace sph {

PressureSolverEntry WcsphSolver::entry() {
  return {"wcsph",
          {common::ConfigSectionEntry::of<WcsphConfig>("wcsph", "WCSPH solver settings")},
          {},
          [](const PhysicsContext& physics) -> std::unique_ptr<PressureSolver> {
            return std::make_unique<WcsphSolver>(physics.settings<WcsphConfig>("wcsph"),
                                                 physics.particle_diameter(), physics.time_step.cfl,
                                                 physics.materials.water.density);
          }};
}

WcsphSolver::WcsphSolver(const WcsphConfig& config, Real particle_diameter, Real cfl,
                         Real reference_density)
    : config_(config),
      sound_speed_(config.sound_speed_factor * config.expected_max_velocity),
      acoustic_dt_limit_(cfl * Real(0.4) * particle_diameter / sound_speed_),
      reference_density_(reference_density) {}

void WcsphSolver::step(SolverHost& host, StepStats& stats) {
  FluidParticles& fluid = host.mutable_fluid();
  host.update_neighbourhood();
  const ParticleNeighbourhood& nb = host.neighbourhood();
  const long n = long(fluid.active_count());
  const Real dt = host.choose_time_step(acoustic_dt_limit_);
  host.compute_non_pressure_accelerations(dt);
  after_non_pressure_forces(host, dt);

  const auto t0 = std::chrono::steady_clock::now();
  const Real gamma = config_.stiffness_exponent;
  const SumAndLargest errors = sum_and_largest(fluid.active_count(), [&](Index i) {
    const Real stiffness = reference_density_ * sound_speed_ * sound_speed_ / gamma;
    fluid.pressure[i] =
        std::max(stiffness * (std::pow(fluid.density[i], gamma) - Real(1)), Real(0));
    const Real error = std::max(fluid.density[i] - Real(1), Real(0));
    return Contribution{error, error};
  });
  // Number-density form (Solenthaler & Pajarola 2008): a_i = -(rho_ref / rho0_i) sum_j V_j
  // (kappa_i + kappa_j) grad W_ij - (rho_ref / rho0_i) kappa_i sum_b V_b grad W_ib with
  // kappa = p / (rho_ref (rho/rho0)^2); V_j is folded into the stored gradients. With one phase
  // this is the usual -sum_j m_j (p_i / rho_i^2 + p_j / rho_j^2) grad W_ij.
  const Real inv_reference = Real(1) / reference_density_;
  for_each_active(fluid, [&](Index i) {
    auto kappa = [&](Index j) {
      return fluid.pressure[j] * inv_reference / (fluid.density[j] * fluid.density[j]);
    };
    const Real ki = kappa(i);
    Vec3 a = -ki * nb.boundary_gradient_sum[i];
    nb.fluid.for_each(i, [&](Index j, Index k) { a -= (ki + kappa(j)) * nb.fluid.gradient[k]; });
    a *= reference_density_ / fluid.rest_density[i];
    fluid.acceleration[i] += a;
  });
  for_each_active(fluid, [&](Index i) {
    fluid.velocity[i] += dt * fluid.acceleration[i];
    fluid.position[i] += dt * fluid.velocity[i];
  });
  host.time_split().pressure_solve += common::seconds_since(t0);
  stats.dt = dt;
  stats.iterations_density = 0;
  stats.iterations_divergence = 0;
  stats.density_error_avg = n > 0 ? errors.sum / double(n) : 0;
  stats.density_error_max = double(errors.largest);
}

}  // namespace sph
