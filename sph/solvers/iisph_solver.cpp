#include "sph/solvers/iisph_solver.h"

#include <algorithm>
#include <chrono>
#include <limits>

#include "common/stopwatch.h"
#include "sph/core/particle_loops.h"
#include "sph/solvers/pressure_terms.h"

namespace sph {

PressureSolverEntry IisphSolver::entry() {
  return {"iisph",
          {common::ConfigSectionEntry::of<IisphConfig>("iisph", "IISPH solver settings")},
          {},
          [](const PhysicsContext& physics) -> std::unique_ptr<PressureSolver> {
            return std::make_unique<IisphSolver>(physics.settings<IisphConfig>("iisph"),
                                                 physics.materials.water.density);
          }};
}

IisphSolver::IisphSolver(const IisphConfig& config, Real reference_density)
    : config_(config), reference_density_(reference_density) {}

void IisphSolver::permute(const std::vector<Index>& order) {
  std::vector<Real> scratch;
  permute_array(stiffness_, order, scratch);
}

void IisphSolver::step(SolverHost& host, StepStats& stats) {
  FluidParticles& fluid = host.mutable_fluid();
  const size_t size = fluid.size();
  alpha_.resize(size, 0);
  stiffness_.resize(size, 0);
  source_.resize(size, 0);
  error_.resize(size, 0);
  pressure_dv_.resize(size, Vec3::Zero());

  host.update_neighbourhood();
  const ParticleNeighbourhood& nb = host.neighbourhood();
  const Index n = fluid.active_count();
  const long count = long(n);

  auto t0 = std::chrono::steady_clock::now();
  pressure_terms::density_ratios(fluid, reference_density_, density_ratio_);
  pressure_terms::compute_factors(nb, density_ratio_, n, alpha_);
  host.time_split().pressure_solve += common::seconds_since(t0);

  const Real dt = host.choose_time_step(std::numeric_limits<Real>::infinity());
  host.compute_non_pressure_accelerations(dt);

  t0 = std::chrono::steady_clock::now();
  const Real relax = std::min(Real(1), dt / config_.density_relaxation_time);
  for_each_active(fluid, [&](Index i) { fluid.velocity[i] += dt * fluid.acceleration[i]; });
  for_each_active(fluid, [&](Index i) {
    source_[i] = relax * (fluid.density[i] - Real(1)) +
                 dt * pressure_terms::density_rate(i, fluid.velocity.data(), nb);
  });
  for (long li = 0; li < count; ++li)
    stiffness_[size_t(li)] = config_.warm_start ? Real(0.5) * stiffness_[size_t(li)] : Real(0);

  const double tolerance = double(config_.density_error_percent) * 0.01;
  const Real omega = config_.omega;
  int iterations = 0;
  double error_avg = 0;
  Real error_max = 0;
  while (true) {
    pressure_terms::stiffness_velocity_change(
        nb, stiffness_, density_ratio_, dt, n,
        [&](Index i, const Vec3& dv) { pressure_dv_[i] = dv; });
    if (count == 0) break;
    const SumAndLargest errors = sum_and_largest(n, [&](Index i) {
      error_[i] = source_[i] + dt * pressure_terms::density_rate(i, pressure_dv_.data(), nb);
      return Contribution{std::max(error_[i], Real(0)), error_[i]};
    });
    error_avg = errors.sum / double(count);
    error_max = errors.largest;
    if ((error_avg <= tolerance && iterations >= config_.min_iterations) ||
        iterations >= config_.max_iterations)
      break;
    for (long li = 0; li < count; ++li) {
      const size_t i = size_t(li);
      stiffness_[i] = std::max(Real(0), stiffness_[i] + omega * alpha_[i] * error_[i]);
    }
    ++iterations;
  }
  host.time_split().pressure_solve += common::seconds_since(t0);
  stats.iterations_density = iterations;
  stats.iterations_divergence = 0;
  stats.density_error_avg = error_avg;
  stats.density_error_max = double(error_max);
  stats.dt = dt;

  const Real inv_dt2 = Real(1) / (dt * dt);
  for_each_active(fluid, [&](Index i) {
    fluid.velocity[i] += pressure_dv_[i];
    fluid.position[i] += dt * fluid.velocity[i];
    fluid.pressure[i] =
        reference_density_ * fluid.density[i] * fluid.density[i] * stiffness_[i] * inv_dt2;
  });
}

}  // namespace sph
