#pragma once
// Position based fluids, Macklin and Mueller, "Position Based Fluids", ACM TOG 32(4), 2013.
//
// Step (the paper's Algorithm 1): non-pressure forces at the current positions -> CFL time step
// -> predicted velocities and positions -> neighbour search on the predicted positions -> a fixed
// number of constraint iterations -> velocities from the position change -> vorticity
// confinement and XSPH viscosity.
//
// Each particle's density constraint is C_i = rho_i/rho0_i - 1 (eq. 1) in the number-density
// formulation of dfsph_solver.h, enforced as a one-sided constraint (only compression, C_i >= 0,
// as the reference implementation SPlisHSPlasH does, so the free surface does not stick). With
// the pair gradients g_ij = V_j grad W_ij and the inverse-mass weights r_i = rho_ref / rho0_i of
// mass-weighted position-based dynamics (a light oil particle moves more under the same
// constraint force, which is buoyancy):
//   lambda_i = -C_i / (r_i |sum_j g_ij + gb_i|^2 + sum_j r_j |g_ij|^2 + epsilon)      (eq. 11)
//   dx_i = r_i [ sum_j (lambda_i + lambda_j + s_corr,ij) g_ij + lambda_i gb_i ]        (eq. 14)
//   s_corr,ij = -k d^2 (W(x_ij) / W(delta_q h))^n                                       (eq. 13)
// The boundary (Akinci volumes) enters C_i and mirrors lambda_i as in DFSPH. epsilon is given in
// units of 1/d^2 and k in units of d^2 (d: particle diameter), so that both keep their meaning
// at any resolution.
//
// The kernels are evaluated on the pairs found for the predicted positions. Between iterations
// the constraints follow the corrections to first order, rho_i += sum_j g_ij . (dx_i - dx_j) +
// gb_i . dx_i, with the gradients (and the lambda denominators) of the predicted positions:
// the corrections are ~1e-3 of the support radius, so the neglected terms are ~1e-6 of rho, far
// below the 1e-4 the solve aims at, and the update is one pass over the pairs where
// re-evaluating the kernel of each pair (the paper's scheme, kernels_every_iteration) cost 40 %
// of the step. After the last iteration the kernels are evaluated exactly at the final
// positions (ParticleNeighbourhood::update_pair_kernels): the reported density error, the
// velocity filters and the next step's forces use those.
//
// The sum of -lambda over an iteration sequence is the dt-free stiffness of DFSPH (s = kappa dt^2;
// dx = dt dv), so the reported pressure is p = rho_ref (rho/rho0)^2 (-sum lambda) / dt^2.
// Vorticity confinement (eq. 15-16): omega_i = sum_j g_ij x (v_j - v_i), f_i = strength (N x
// omega_i) with N the direction of grad |omega|. XSPH (eq. 17): v_i += c sum_j V_j W_ij (v_j -
// v_i).

#include "sph/solvers/pressure_solver.h"

namespace sph {

// Scene key `pbf`.
struct PbfConfig {
  int iterations = 4;
  Real relaxation_epsilon = Real(1e-3);
  Real tensile_k = Real(0.1);
  Real tensile_n = 4;
  Real tensile_delta_q = Real(0.2);
  Real xsph = Real(0.01);
  Real vorticity_confinement = Real(0.01);
  bool kernels_every_iteration = false;
  template <class V>
  void describe(V& v) {
    v.field("iterations", iterations,
            param("", "Constraint iterations per step").at_least(1).at_most(1000));
    v.field("relaxation_epsilon", relaxation_epsilon,
            param("1/d^2",
                  "Constraint force mixing epsilon added to each constraint's gradient norm "
                  "(in units of 1 / particle diameter^2); softens sparse neighbourhoods")
                .non_negative()
                .at_most(1e6));
    v.field("tensile_k", tensile_k,
            param("d^2",
                  "Strength k of the artificial pressure s_corr against clustering (in units "
                  "of particle diameter^2; 0: off)")
                .non_negative()
                .at_most(10));
    v.field("tensile_n", tensile_n,
            param("", "Exponent n of the artificial pressure").at_least(1).at_most(16));
    v.field("tensile_delta_q", tensile_delta_q,
            param("h", "Distance delta_q of the artificial pressure, in support radii")
                .positive()
                .at_most(1));
    v.field("xsph", xsph,
            param("", "XSPH viscosity coefficient c applied after the velocity update")
                .non_negative()
                .at_most(1));
    v.field("vorticity_confinement", vorticity_confinement,
            param("m/s", "Strength of the vorticity confinement force (0: off)").non_negative());
    v.field("kernels_every_iteration", kernels_every_iteration,
            param("",
                  "Re-evaluate every pair's kernel at the corrected positions in each iteration "
                  "(the paper's scheme, 1.5 x the cost per step) instead of updating each "
                  "constraint to first order in the corrections; the end state is the same "
                  "to the solver's tolerance"));
  }
};

class PbfSolver : public PressureSolver {
 public:
  PbfSolver(const PbfConfig& config, Real particle_diameter, Real reference_density);
  static PressureSolverEntry entry();
  std::string name() const override { return "pbf"; }
  void step(SolverHost& host, StepStats& stats) override;
  // The neighbourhood kept between steps is checked against the positions instead.
  void permute(const std::vector<Index>&) override {}

 private:
  // One constraint iteration: moves the positions, adds -lambda to stiffness_. With
  // fresh_kernels the kernels are at the current positions and the lambda denominators are
  // computed from them; otherwise the densities are first moved to first order by the last
  // iteration's corrections and the stored denominators are used.
  void project_constraints(FluidParticles& fluid, const ParticleNeighbourhood& nb,
                           bool fresh_kernels);
  // Vorticity confinement and XSPH on the velocities, at the final positions' kernels.
  void filter_velocities(FluidParticles& fluid, const ParticleNeighbourhood& nb, Real dt);

  PbfConfig config_;
  Real diameter_;
  Real reference_density_;
  std::vector<Real> density_ratio_;  // [n] r_i = rho_ref / rho0_i
  std::vector<Real> lambda_;         // [n] of the current iteration
  std::vector<Real> stiffness_;      // [n] -sum of lambda over the step (for the pressure)
  std::vector<Vec3> old_position_;   // [n] positions at the start of the step
  std::vector<Real> denominator_;    // [n] 1 / alpha_i of the kernels in use
  std::vector<Vec3> correction_;     // [n] position change of the iteration
  std::vector<Vec3> vorticity_;      // [n]
  std::vector<Vec3> new_velocity_;   // [n]
  std::vector<Vec3> end_position_;   // [n] positions of the last step's final kernels
};

}  // namespace sph
