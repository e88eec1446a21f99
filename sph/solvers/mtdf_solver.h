#pragma once
// MTDF-SPH: DFSPH's divergence-free and constant-density solves with the two-phase mixture model
// (mixture_model.h) and the cosine-force surface tension (surface_tension_force.h, which its
// registry entry adds to the non-pressure forces).
//
// One step, in the order of the paper's Algorithms 1-3:
//   neighbours and densities -> drift velocities of the mixture model -> factors -> divergence-free
//   solve -> non-pressure forces (gravity, viscosity, surface tension) plus the drift momentum
//   term -> CFL time step -> predicted velocities -> constant-density solve -> positions ->
//   volume-fraction transport, and with it each particle's mixture rest density, viscosity and
//   phase.
// The mixture enters both pressure solves through one per-particle parameter, the ratio
// tau_i = rho_ref / rho_m,i of the reference density to the particle's mixture density: the
// shared pressure field accelerates a particle by tau_i times the water particle's acceleration,
// and the factors alpha_i, computed once per step with the same tau, serve both solves.

#include "sph/solvers/dfsph_solver.h"
#include "sph/solvers/mixture_model.h"

namespace sph {

class MtdfSolver : public DfsphSolver {
 public:
  explicit MtdfSolver(const PhysicsContext& physics);
  static PressureSolverEntry entry();
  std::string name() const override { return "mtdf"; }
  void permute(const std::vector<Index>& order) override;

 protected:
  void after_neighbour_search(SolverHost& host) override;
  void after_non_pressure_forces(SolverHost& host, Real dt) override;
  void after_advection(SolverHost& host, Real dt) override;

 private:
  MixtureModel mixture_;
};

}  // namespace sph
