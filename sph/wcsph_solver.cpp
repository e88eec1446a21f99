#include "sph/wcsph_solver.h"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace sph {

WcsphSolver::WcsphSolver(const WcsphConfig& config, Real particle_diameter, Real cfl)
    : config_(config),
      sound_speed_(config.sound_speed_factor * config.expected_max_velocity),
      acoustic_dt_limit_(cfl * Real(0.4) * particle_diameter / sound_speed_) {}

void WcsphSolver::step(SolverHost& host, StepStats& stats) {
  FluidParticles& fluid = host.mutable_fluid();
  host.update_neighbourhood();
  const ParticleNeighbourhood& nb = host.neighbourhood();
  const long n = long(fluid.active_count());
  const Real dt = host.choose_time_step(acoustic_dt_limit_);
  host.compute_non_pressure_accelerations(dt);

  const auto t0 = std::chrono::steady_clock::now();
  const Real gamma = config_.stiffness_exponent;
  double error_sum = 0;
  Real error_max = 0;
#pragma omp parallel for schedule(dynamic, 64) reduction(+ : error_sum) reduction(max : error_max)
  for (long li = 0; li < n; ++li) {
    const size_t i = size_t(li);
    const Real rho0 = fluid.rest_density[i];
    const Real stiffness = rho0 * sound_speed_ * sound_speed_ / gamma;
    fluid.pressure[i] =
        std::max(stiffness * (std::pow(fluid.density[i], gamma) - Real(1)), Real(0));
    const Real error = std::max(fluid.density[i] - Real(1), Real(0));
    error_sum += double(error);
    error_max = std::max(error_max, error);
  }
  // a_i = -sum_j m_j (p_i / rho_i^2 + p_j / rho_j^2) grad W_ij - sum_b rho0 V_b p_i / rho_i^2 grad
  // W with m_j = rho0 V_j (V_j is folded into the stored gradients): the factor p / (rho0
  // rhohat^2).
#pragma omp parallel for schedule(dynamic, 64)
  for (long li = 0; li < n; ++li) {
    const Index i = Index(li);
    auto pressure_term = [&](Index j) {
      return fluid.pressure[j] / (fluid.rest_density[j] * fluid.density[j] * fluid.density[j]);
    };
    const Real ti = pressure_term(i);
    Vec3 a = -ti * nb.boundary_gradient_sum[i];
    nb.fluid.for_each(
        i, [&](Index j, Index k) { a -= (ti + pressure_term(j)) * nb.fluid.gradient[k]; });
    fluid.acceleration[i] += a;
  }
#pragma omp parallel for schedule(dynamic, 64)
  for (long li = 0; li < n; ++li) {
    const size_t i = size_t(li);
    fluid.velocity[i] += dt * fluid.acceleration[i];
    fluid.position[i] += dt * fluid.velocity[i];
  }
  host.time_split().pressure_solve +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  stats.dt = dt;
  stats.iterations_density = 0;
  stats.iterations_divergence = 0;
  stats.density_error_avg = n > 0 ? error_sum / double(n) : 0;
  stats.density_error_max = double(error_max);
}

}  // namespace sph
