#pragma once
// Implicit incompressible SPH, Ihmsen, Cornelis, Solenthaler, Horvath and Teschner, "Implicit
// Incompressible SPH", IEEE TVCG 20(3), 2014.
//
// Step: neighbours, densities, diagonal factors -> non-pressure forces -> CFL time step ->
// predicted velocities v* -> pressure Poisson equation by relaxed Jacobi -> velocities ->
// positions. The equation asks that the pressure accelerations of this step bring every
// particle's rho/rho0 to 1:
//   e_i(s) = r (rho_i/rho0 - 1) + dt [ D(v*)_i + D(dv(s))_i ] = 0,
// where D(v)_i = sum_j (v_i - v_j) . g_ij + v_i . gb_i is the rate of change of rho/rho0 and
// dv(s) the velocity change of the stiffness field s = kappa dt^2 (pressure_terms.h; kappa =
// p / (rho_ref (rho/rho0)^2), so p = rho_ref (rho/rho0)^2 s / dt^2). The diagonal of the map
// s -> e is -1/alpha_i, the paper's a_ii (eq. 12) in these units, and its Jacobi update with
// relaxation omega is
//   s_i <- max(0, s_i + omega alpha_i e_i(s))      (paper eq. 14; negative pressures clamped)
// Each iteration evaluates dv(s) and then e(s): two passes over the pairs, as the paper's
// splitting into d_ij terms does, without storing them. Warm start: half of the previous step's
// s (the paper's 0.5 p(t - dt)); stopping: the mean of max(e_i, 0) below density_error_percent,
// the same measure and default as DFSPH's constant-density solve, after at least
// min_iterations. As DFSPH does, an error the step starts with is removed over
// density_relaxation_time (r = min(1, dt / time)), so short steps do not set water at rest in
// motion. Boundaries: Akinci volumes with the particle's own pressure mirrored, and phases of
// different rest density through the number-density formulation, both as in dfsph_solver.h.

#include "sph/solvers/pressure_solver.h"

namespace sph {

// Scene key `iisph`.
struct IisphConfig {
  Real density_error_percent = Real(0.05);
  Real omega = Real(0.5);
  int min_iterations = 2;
  int max_iterations = 100;
  bool warm_start = true;
  Real density_relaxation_time = Real(5e-4);
  template <class V>
  void describe(V& v) {
    v.field("density_error_percent", density_error_percent,
            param("%", "Stop when the mean predicted density error is below this")
                .positive()
                .at_most(10));
    v.field("omega", omega, param("", "Relaxation of the Jacobi iteration").positive().at_most(1));
    v.field("min_iterations", min_iterations,
            param("", "Fewest Jacobi iterations per step").at_least(0).at_most(1000));
    v.field("max_iterations", max_iterations,
            param("", "Most Jacobi iterations per step").at_least(1).at_most(10000));
    v.field("warm_start", warm_start, param("", "Start from half of the previous step's pressure"));
    v.field("density_relaxation_time", density_relaxation_time,
            param("s",
                  "A density error present at the start of a step is removed over this time "
                  "(as DFSPH's setting of the same name)")
                .positive()
                .at_most(1));
  }
  void check(const std::string& file, const std::string& pointer) const {
    if (min_iterations > max_iterations)
      throw ConfigError(file, pointer + "/min_iterations",
                        "expected <= " + pointer + "/max_iterations");
  }
};

class IisphSolver : public PressureSolver {
 public:
  IisphSolver(const IisphConfig& config, Real reference_density);
  static PressureSolverEntry entry();
  std::string name() const override { return "iisph"; }
  void step(SolverHost& host, StepStats& stats) override;
  void permute(const std::vector<Index>& order) override;

 private:
  IisphConfig config_;
  Real reference_density_;
  std::vector<Real> density_ratio_;  // [n] r_i = rho_ref / rho0_i
  std::vector<Real> alpha_;          // [n] minus the inverse diagonal
  std::vector<Real> stiffness_;      // [n] s of this step (the next step's warm start)
  std::vector<Real> source_;         // [n] predicted error without pressure
  std::vector<Real> error_;          // [n] predicted error with the current s
  std::vector<Vec3> pressure_dv_;    // [n] dv(s)
};

}  // namespace sph
