#include "sph/solvers/pbf_solver.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "common/stopwatch.h"
#include "sph/core/particle_loops.h"
#include "sph/solvers/pressure_terms.h"

namespace sph {

PressureSolverEntry PbfSolver::entry() {
  return {"pbf",
          {common::ConfigSectionEntry::of<PbfConfig>("pbf", "PBF solver settings")},
          {},
          [](const PhysicsContext& physics) -> std::unique_ptr<PressureSolver> {
            return std::make_unique<PbfSolver>(physics.settings<PbfConfig>("pbf"),
                                               physics.particle_diameter(),
                                               physics.materials.water.density);
          }};
}

PbfSolver::PbfSolver(const PbfConfig& config, Real particle_diameter, Real reference_density)
    : config_(config), diameter_(particle_diameter), reference_density_(reference_density) {}

void PbfSolver::project_constraints(FluidParticles& fluid, const ParticleNeighbourhood& nb,
                                    bool fresh_kernels) {
  const Real epsilon = config_.relaxation_epsilon / (diameter_ * diameter_);
  const Real tiny = pressure_terms::smallest_factor_denominator(nb);
  // lambda_i = -C_i / (1/alpha_i + epsilon), with 1/alpha_i from pressure_terms.h.
  for_each_active(fluid, [&](Index i) {
    if (fresh_kernels) {
      denominator_[i] = pressure_terms::factor_denominator(i, nb, density_ratio_);
    } else {
      // The last correction's first-order change of rho_i (see the header).
      fluid.density[i] += pressure_terms::density_change(i, nb, correction_);
    }
    const Real c = std::max(fluid.density[i] - Real(1), Real(0));
    // Only compressed particles need it (C_i > 0).
    const Real lambda = c > 0 && denominator_[i] > tiny ? -c / (denominator_[i] + epsilon) : 0;
    lambda_[i] = lambda;
    stiffness_[i] -= lambda;
  });

  const Real k = config_.tensile_k * diameter_ * diameter_;
  const Real w_delta_q = with_kernel(nb.kernel(), nb.support_radius(), [&](const auto& w) {
    return w.value(config_.tensile_delta_q * nb.support_radius());
  });
  const Real inv_w_delta_q = w_delta_q > 0 ? Real(1) / w_delta_q : Real(0);
  const Real exponent = config_.tensile_n;
  const int whole_exponent = int(exponent) == exponent ? int(exponent) : 0;
  auto tensile_power = [&](Real x) {
    if (whole_exponent == 0) return std::pow(x, exponent);
    Real p = x;
    for (int e = 1; e < whole_exponent; ++e) p *= x;
    return p;
  };
  const bool tensile = k > 0;
  for_each_active(fluid, [&](Index i) {
    const Real lambda_i = lambda_[i];
    Vec3 dx = lambda_i * nb.boundary_gradient_sum[i];
    nb.fluid.for_each(i, [&](Index j, Index kk) {
      Real s = lambda_i + lambda_[j];
      if (tensile) s -= k * tensile_power(nb.fluid.value[kk] * inv_w_delta_q);
      dx += s * nb.fluid.gradient[kk];
    });
    correction_[i] = density_ratio_[i] * dx;
  });
  for_each_active(
      fluid, [&](Index i) { fluid.position[i] += correction_[i]; }, Schedule::kStatic);
}

void PbfSolver::filter_velocities(FluidParticles& fluid, const ParticleNeighbourhood& nb, Real dt) {
  const long n = long(fluid.active_count());
  const Vec3* v = fluid.velocity.data();
  const bool confine = config_.vorticity_confinement > 0;
  if (confine) {
    for_each_active(fluid, [&](Index i) {
      Vec3 w = Vec3::Zero();
      nb.fluid.for_each(i, [&](Index j, Index k) { w += nb.fluid.gradient[k].cross(v[j] - v[i]); });
      vorticity_[i] = w;
    });
  }
  const Real c = config_.xsph;
  for_each_active(fluid, [&](Index i) {
    Vec3 smoothing = Vec3::Zero();
    Vec3 eta = Vec3::Zero();
    const Real wi = confine ? vorticity_[i].norm() : Real(0);
    nb.fluid.for_each(i, [&](Index j, Index k) {
      smoothing += (fluid.rest_volume[j] * nb.fluid.value[k]) * (v[j] - v[i]);
      if (confine) eta += (vorticity_[j].norm() - wi) * nb.fluid.gradient[k];
    });
    Vec3 dv = c * smoothing;
    const Real eta_norm = eta.norm();
    if (confine && eta_norm > Real(1e-12))
      dv += dt * config_.vorticity_confinement * (eta / eta_norm).cross(vorticity_[i]);
    new_velocity_[i] = v[i] + dv;
  });
  std::copy(new_velocity_.begin(), new_velocity_.begin() + n, fluid.velocity.begin());
}

void PbfSolver::step(SolverHost& host, StepStats& stats) {
  FluidParticles& fluid = host.mutable_fluid();
  const size_t size = fluid.size();
  lambda_.resize(size, 0);
  denominator_.resize(size, 0);
  stiffness_.resize(size, 0);
  old_position_.resize(size);
  correction_.resize(size);
  vorticity_.resize(size);
  new_velocity_.resize(size);

  // Forces at the current positions. The last step's final kernels were evaluated at exactly
  // these positions: unless particles were added, removed, reordered or moved since, they are
  // the neighbourhood of now (pairs that came within reach during that step's corrections, a
  // fraction of the support radius, aside), and a second search per step is saved.
  const Index n = fluid.active_count();
  const bool unchanged =
      n == Index(end_position_.size()) &&
      std::equal(end_position_.begin(), end_position_.end(), fluid.position.begin());
  if (!unchanged) host.update_neighbourhood();
  const long count = long(n);
  const Real dt = host.choose_time_step(std::numeric_limits<Real>::infinity());
  host.compute_non_pressure_accelerations(dt);

  auto t0 = std::chrono::steady_clock::now();
  pressure_terms::density_ratios(fluid, reference_density_, density_ratio_);
  for_each_particle(
      Index(count),
      [&](Index i) {
        old_position_[i] = fluid.position[i];
        fluid.velocity[i] += dt * fluid.acceleration[i];
        fluid.position[i] += dt * fluid.velocity[i];
        stiffness_[i] = 0;
      },
      Schedule::kStatic);
  host.time_split().pressure_solve += common::seconds_since(t0);

  // Constraints at the predicted positions.
  host.update_neighbourhood();
  const ParticleNeighbourhood& nb = host.neighbourhood();
  for (int it = 0; it < config_.iterations; ++it) {
    const bool fresh = it == 0 || config_.kernels_every_iteration;
    if (it > 0 && fresh) host.update_pair_kernels();
    t0 = std::chrono::steady_clock::now();
    project_constraints(fluid, nb, fresh);
    host.time_split().pressure_solve += common::seconds_since(t0);
  }
  host.update_pair_kernels();

  t0 = std::chrono::steady_clock::now();
  const Real inv_dt = Real(1) / dt, inv_dt2 = inv_dt * inv_dt;
  const SumAndLargest errors = sum_and_largest(
      n,
      [&](Index i) {
        fluid.velocity[i] = (fluid.position[i] - old_position_[i]) * inv_dt;
        fluid.pressure[i] =
            reference_density_ * fluid.density[i] * fluid.density[i] * stiffness_[i] * inv_dt2;
        const Real error = std::max(fluid.density[i] - Real(1), Real(0));
        return Contribution{error, error};
      },
      Schedule::kStatic);
  if (config_.xsph > 0 || config_.vorticity_confinement > 0) filter_velocities(fluid, nb, dt);
  end_position_.assign(fluid.position.begin(), fluid.position.begin() + count);
  host.time_split().pressure_solve += common::seconds_since(t0);

  stats.dt = dt;
  stats.iterations_density = config_.iterations;
  stats.iterations_divergence = 0;
  stats.density_error_avg = count > 0 ? errors.sum / double(count) : 0;
  stats.density_error_max = double(errors.largest);
}

}  // namespace sph
