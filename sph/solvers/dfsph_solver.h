#pragma once
// Divergence-free SPH, Bender & Koschier, "Divergence-Free SPH for Incompressible and Turbulent
// Flows", SCA 2015, and "Divergence-Free Smoothed Particle Hydrodynamics", IEEE TVCG 23(3), 2017.
//
// Step (the 2017 paper's Algorithm 1, started at the neighbour search):
//   neighbours, densities, factors alpha_i (eq. 11 of the 2015 paper)
//   -> divergence-free solve (Algorithm 2) -> non-pressure forces -> CFL time step
//   -> predicted velocities -> constant-density solve (Algorithm 3) -> positions.
//
// We write both solves with a dt-free stiffness s_i (units m^2): the velocity change is
//   dv_i = -(1/dt) [ sum_j V_j (s_i + s_j) grad W_ij + sum_b V_b s_i grad W_ib ],
// the constant-density solve sets s_i = max(rho*_i/rho0 - 1, 0) alpha_i and the divergence solve
// s_i = dt max(D rho_i/Dt / rho0, 0) alpha_i, which is the paper's kappa_i times dt^2 (eq. 8-10).
// Being dt-free, the stiffness summed over one step's iterations warm-starts the next step even
// when dt changes.
//
// The constant-density solve targets rho*_i/rho0 - 1 = r (rho_i/rho0 - 1) + dt D rho_i/Dt / rho0
// with r = min(1, dt / density_relaxation_time): the compression this step's velocities would
// cause is removed in full, a density error the step starts with only in part. Removing an error
// e within one step takes a velocity of about e h / dt, which stays in the particles; at small dt
// (1e-5 s) the solver's own tolerance-level residual then sets water at rest in motion at
// m/s. Spreading it over a fixed time, as Baumgarte's stabilisation of drifting constraints does,
// bounds that velocity by e h / density_relaxation_time; at steps of at least that length the
// solve is plain DFSPH.
//
// Phases of different rest density (oil on water) use the number-density formulation of
// Solenthaler & Pajarola, "Density contrast SPH interfaces", SCA 2008: the solves make the kernel
// sum of volumes rho/rho0 equal 1 for every particle, the pressure field is shared, and a
// particle's pressure acceleration is scaled by r_i = rho_ref / rho0_i (rho_ref: water), so the
// same pressure lifts light oil more than water (buoyancy) and pair forces stay equal and
// opposite. Then dv_i = -(r_i/dt) [...] above and alpha_i = 1 / (r_i |sum_j V_j grad W_ij +
// sum_b V_b grad W_ib|^2 + sum_j r_j |V_j grad W_ij|^2). With one phase r = 1 everywhere. Boundary
// particles mirror the fluid particle's pressure (Akinci et al. 2012), which is why the boundary
// terms carry s_i only; alpha_i includes their gradients accordingly.

#include "sph/solvers/pressure_solver.h"

namespace sph {

// The settings of both solves (scene key `dfsph`; MTDF-SPH reads them too).
struct DfsphConfig {
  Real density_error_percent = Real(0.05);
  Real divergence_error_percent = Real(0.1);
  int min_iterations_density = 2;
  int min_iterations_divergence = 1;
  int max_iterations = 100;
  bool warm_start = true;
  bool divergence_solver = true;
  Real density_relaxation_time = Real(5e-4);
  template <class V>
  void describe(V& v) {
    v.field("density_error_percent", density_error_percent,
            param("%", "Stop the constant-density solve when the mean density error is below this")
                .positive()
                .at_most(10));
    v.field("divergence_error_percent", divergence_error_percent,
            param("%",
                  "Stop the divergence-free solve when the mean density change per step is "
                  "below this")
                .positive()
                .at_most(10));
    v.field("min_iterations_density", min_iterations_density,
            param("", "Fewest iterations of the constant-density solve").at_least(0).at_most(1000));
    v.field("min_iterations_divergence", min_iterations_divergence,
            param("", "Fewest iterations of the divergence-free solve").at_least(0).at_most(1000));
    v.field("max_iterations", max_iterations,
            param("", "Most iterations of each solve").at_least(1).at_most(10000));
    v.field("warm_start", warm_start,
            param("", "Start each solve from the previous step's pressure"));
    v.field("divergence_solver", divergence_solver,
            param("", "Run the divergence-free solve (off: constant-density solve only)"));
    v.field("density_relaxation_time", density_relaxation_time,
            param("s",
                  "A density error already present at the start of a step is corrected over "
                  "this time, not within one step: steps shorter than it remove the fraction "
                  "dt / time of it, so the velocity the correction leaves behind stays about "
                  "error x support radius / time instead of growing as 1 / dt (at 1e-5 s steps "
                  "a tank at rest otherwise boils at 45 m/s); steps at least this long correct "
                  "it fully, as plain DFSPH does")
                .positive()
                .at_most(1));
  }
  void check(const std::string& file, const std::string& pointer) const {
    if (min_iterations_density > max_iterations)
      throw ConfigError(file, pointer + "/min_iterations_density",
                        "expected <= " + pointer + "/max_iterations");
    if (min_iterations_divergence > max_iterations)
      throw ConfigError(file, pointer + "/min_iterations_divergence",
                        "expected <= " + pointer + "/max_iterations");
  }
};

class DfsphSolver : public PressureSolver {
 public:
  DfsphSolver(const DfsphConfig& config, Real initial_dt, Real reference_density);
  static PressureSolverEntry entry();
  std::string name() const override { return "dfsph"; }
  void step(SolverHost& host, StepStats& stats) override;
  void permute(const std::vector<Index>& order) override;

 protected:
  // Points where a solver built on DFSPH (MTDF-SPH) adds its own work to the step.
  // After the neighbour search, before the factors.
  virtual void after_neighbour_search(SolverHost&) {}
  // After the non-pressure accelerations of step dt, before they change the velocities.
  virtual void after_non_pressure_forces(SolverHost&, Real /*dt*/) {}
  // At the end of the step, after the positions moved by dt.
  virtual void after_advection(SolverHost&, Real /*dt*/) {}

 private:
  int solve_divergence(FluidParticles& fluid, const ParticleNeighbourhood& nb, Real dt);
  int solve_density(FluidParticles& fluid, const ParticleNeighbourhood& nb, Real dt,
                    StepStats& stats);
  // The iteration both solves share: s_i = predicted_error(i) alpha_i, velocities corrected
  // until the mean predicted error is below `tolerance`; stiffness_total sums s over the step.
  template <class PredictedError>
  int solve(FluidParticles& fluid, const ParticleNeighbourhood& nb, Real dt,
            std::vector<Real>& stiffness_total, double tolerance, int min_iterations,
            PredictedError predicted_error, double& error_avg, double& error_max);
  // dv_i = -(1/dt) [sum_j V_j (s_i + s_j) grad W_ij + sum_b V_b s_i grad W_ib] for all i.
  void apply_stiffness(FluidParticles& fluid, const ParticleNeighbourhood& nb,
                       const std::vector<Real>& s, Real dt) const;

  DfsphConfig config_;
  Real last_dt_;
  Real reference_density_;
  std::vector<Real> density_ratio_;         // [n] r_i = rho_ref / rho0_i
  std::vector<Real> alpha_;                 // [n] 1 / (|sum V grad W|^2 + sum |V grad W|^2)
  std::vector<Real> stiffness_density_;     // [n] sum of s over this step's density iterations
  std::vector<Real> stiffness_divergence_;  // [n] same for the divergence solve
  std::vector<Real> s_;                     // [n] stiffness of the current iteration
};

}  // namespace sph
