#include "sph/solvers/dfsph_solver.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "common/stopwatch.h"
#include "sph/core/particle_loops.h"
#include "sph/solvers/pressure_terms.h"

namespace sph {

namespace {

// Fewer neighbours than this marks a particle near the free surface, whose density deficit is not
// compression: the divergence solve leaves it alone (as the reference implementation does).
constexpr Index kMinNeighboursForDivergence = 20;

inline Real density_rate(Index i, const FluidParticles& fluid, const ParticleNeighbourhood& nb) {
  return pressure_terms::density_rate(i, fluid.velocity.data(), nb);
}

}  // namespace

PressureSolverEntry DfsphSolver::entry() {
  return {"dfsph",
          {common::ConfigSectionEntry::of<DfsphConfig>("dfsph", "DFSPH solver settings")},
          {},
          [](const PhysicsContext& physics) -> std::unique_ptr<PressureSolver> {
            return std::make_unique<DfsphSolver>(physics.settings<DfsphConfig>("dfsph"),
                                                 physics.time_step.dt_max,
                                                 physics.materials.water.density);
          }};
}

DfsphSolver::DfsphSolver(const DfsphConfig& config, Real initial_dt, Real reference_density)
    : config_(config), last_dt_(initial_dt), reference_density_(reference_density) {}

void DfsphSolver::permute(const std::vector<Index>& order) {
  std::vector<Real> scratch;
  permute_array(stiffness_density_, order, scratch);
  permute_array(stiffness_divergence_, order, scratch);
}

void DfsphSolver::apply_stiffness(FluidParticles& fluid, const ParticleNeighbourhood& nb,
                                  const std::vector<Real>& s, Real dt) const {
  pressure_terms::stiffness_velocity_change(
      nb, s, density_ratio_, dt, fluid.active_count(),
      [&](Index i, const Vec3& dv) { fluid.velocity[i] += dv; });
}

template <class PredictedError>
int DfsphSolver::solve(FluidParticles& fluid, const ParticleNeighbourhood& nb, Real dt,
                       std::vector<Real>& stiffness_total, double tolerance, int min_iterations,
                       PredictedError predicted_error, double& error_avg, double& error_max) {
  const long n = long(fluid.active_count());
  error_avg = error_max = 0;
  if (n == 0) return 0;
  // Warm start with half of last step's stiffness (the full amount overshoots and, since only
  // compression is corrected, an overshoot is never taken back), then iterate on what is left.
  if (config_.warm_start) {
    for (long i = 0; i < n; ++i) s_[size_t(i)] = Real(0.5) * stiffness_total[size_t(i)];
    apply_stiffness(fluid, nb, s_, dt);
    std::copy(s_.begin(), s_.begin() + n, stiffness_total.begin());
  } else {
    std::fill(stiffness_total.begin(), stiffness_total.begin() + n, Real(0));
  }
  int iterations = 0;
  while (true) {
    const SumAndLargest errors = sum_and_largest(Index(n), [&](Index i) {
      const Real error = predicted_error(i);  // >= 0: relative compression after this step
      s_[i] = error * alpha_[i];
      return Contribution{error, error};
    });
    error_avg = errors.sum / double(n);
    error_max = double(errors.largest);
    if ((error_avg <= tolerance && iterations >= min_iterations) ||
        iterations >= config_.max_iterations)
      break;
    apply_stiffness(fluid, nb, s_, dt);
    for (long i = 0; i < n; ++i) stiffness_total[size_t(i)] += s_[size_t(i)];
    ++iterations;
  }
  return iterations;
}

int DfsphSolver::solve_divergence(FluidParticles& fluid, const ParticleNeighbourhood& nb, Real dt) {
  // The density change over one step from the current divergence, compression only, and only
  // where a particle has a full neighbourhood.
  auto error_of = [&](Index i) {
    if (nb.fluid.lists.count(i) + nb.boundary.lists.count(i) < kMinNeighboursForDivergence)
      return Real(0);
    return dt * std::max(density_rate(i, fluid, nb), Real(0));
  };
  double avg = 0, max = 0;
  return solve(fluid, nb, dt, stiffness_divergence_,
               double(config_.divergence_error_percent) * 0.01, config_.min_iterations_divergence,
               error_of, avg, max);
}

int DfsphSolver::solve_density(FluidParticles& fluid, const ParticleNeighbourhood& nb, Real dt,
                               StepStats& stats) {
  // The density the predicted velocities would lead to, compression only; an error the step
  // starts with counts with the weight r = min(1, dt / relaxation time) (see the header).
  const Real relax = std::min(Real(1), dt / config_.density_relaxation_time);
  const bool partial = relax < 1;
  auto error_of = [&](Index i) {
    const Real change = dt * density_rate(i, fluid, nb);
    // (Written as before where the whole error counts, so such runs are bit-identical.)
    const Real predicted = partial ? relax * (fluid.density[i] - Real(1)) + change
                                   : fluid.density[i] + change - Real(1);
    return std::max(predicted, Real(0));
  };
  return solve(fluid, nb, dt, stiffness_density_, double(config_.density_error_percent) * 0.01,
               config_.min_iterations_density, error_of, stats.density_error_avg,
               stats.density_error_max);
}

void DfsphSolver::step(SolverHost& host, StepStats& stats) {
  FluidParticles& fluid = host.mutable_fluid();
  const size_t size = fluid.size();
  alpha_.resize(size, 0);
  stiffness_density_.resize(size, 0);
  stiffness_divergence_.resize(size, 0);
  s_.resize(size, 0);
  density_ratio_.resize(size, 1);

  host.update_neighbourhood();
  const ParticleNeighbourhood& nb = host.neighbourhood();
  after_neighbour_search(host);

  auto t0 = std::chrono::steady_clock::now();
  pressure_terms::density_ratios(fluid, reference_density_, density_ratio_);
  pressure_terms::compute_factors(nb, density_ratio_, fluid.active_count(), alpha_);
  stats.iterations_divergence =
      config_.divergence_solver ? solve_divergence(fluid, nb, last_dt_) : 0;
  if (!config_.divergence_solver)
    std::fill(stiffness_divergence_.begin(), stiffness_divergence_.end(), Real(0));
  host.time_split().pressure_solve += common::seconds_since(t0);

  const Real dt = host.choose_time_step(std::numeric_limits<Real>::infinity());
  host.compute_non_pressure_accelerations(dt);
  after_non_pressure_forces(host, dt);
  for_each_active(fluid, [&](Index i) { fluid.velocity[i] += dt * fluid.acceleration[i]; });

  t0 = std::chrono::steady_clock::now();
  stats.iterations_density = solve_density(fluid, nb, dt, stats);
  host.time_split().pressure_solve += common::seconds_since(t0);

  // Pressure for output: p = rho_ref (rho/rho0)^2 kappa with kappa = s / dt^2 of each solve.
  const Real inv_dt2 = Real(1) / (dt * dt), inv_dt2_div = Real(1) / (last_dt_ * last_dt_);
  for_each_active(fluid, [&](Index i) {
    fluid.position[i] += dt * fluid.velocity[i];
    const Real kappa = stiffness_density_[i] * inv_dt2 + stiffness_divergence_[i] * inv_dt2_div;
    fluid.pressure[i] = reference_density_ * fluid.density[i] * fluid.density[i] * kappa;
  });
  stats.dt = dt;
  last_dt_ = dt;
  after_advection(host, dt);
}

}  // namespace sph
