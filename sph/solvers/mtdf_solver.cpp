#include "sph/solvers/mtdf_solver.h"

#include "common/stopwatch.h"

namespace sph {

PressureSolverEntry MtdfSolver::entry() {
  return {"mtdf",
          // It reads DFSPH's settings (registered by DFSPH) and owns the mixture model's.
          {common::ConfigSectionEntry::of<MixtureConfig>("mixture",
                                                         "Mixture model (solver mtdf only)")},
          {"surface_tension"},
          [](const PhysicsContext& physics) -> std::unique_ptr<PressureSolver> {
            return std::make_unique<MtdfSolver>(physics);
          }};
}

MtdfSolver::MtdfSolver(const PhysicsContext& physics)
    : DfsphSolver(physics.settings<DfsphConfig>("dfsph"), physics.time_step.dt_max,
                  physics.materials.water.density),
      mixture_(physics.settings<MixtureConfig>("mixture"), physics.materials, physics.gravity) {}

void MtdfSolver::permute(const std::vector<Index>& order) {
  DfsphSolver::permute(order);
  mixture_.permute(order);
}

void MtdfSolver::after_neighbour_search(SolverHost& host) {
  common::ScopedTimer timer(host.time_split().solver_parts["mixture_model"]);
  mixture_.compute_drift(host.mutable_fluid(), host.neighbourhood());
}

void MtdfSolver::after_non_pressure_forces(SolverHost& host, Real dt) {
  common::ScopedTimer timer(host.time_split().solver_parts["mixture_model"]);
  mixture_.exchange_and_drift_momentum(host.mutable_fluid(), host.neighbourhood(), dt);
}

void MtdfSolver::after_advection(SolverHost& host, Real dt) {
  common::ScopedTimer timer(host.time_split().solver_parts["mixture_model"]);
  mixture_.transport(host.mutable_fluid(), host.neighbourhood(), dt);
}

}  // namespace sph
