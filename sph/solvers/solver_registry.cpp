// The one list of pressure solvers: adding a solver is its file pair, its #include and its line.

#include <stdexcept>

#include "sph/solvers/dfsph_solver.h"
#include "sph/solvers/iisph_solver.h"
#include "sph/solvers/mtdf_solver.h"
#include "sph/solvers/pbf_solver.h"
#include "sph/solvers/pfsph_solver.h"
#include "sph/solvers/pressure_solver.h"
#include "sph/solvers/wcsph_solver.h"

namespace sph {

std::vector<PressureSolverEntry> pressure_solver_entries() {
  return {
      // clang-format off
      DfsphSolver::entry(),
      IisphSolver::entry(),
      MtdfSolver::entry(),
      PbfSolver::entry(),
      PfsphSolver::entry(),
      WcsphSolver::entry(),
      // clang-format on
  };
}

std::vector<std::string> pressure_solver_names() {
  std::vector<std::string> names;
  for (const auto& e : pressure_solver_entries()) names.push_back(e.name);
  return names;
}

PressureSolverEntry pressure_solver_entry(const std::string& name) {
  for (auto& e : pressure_solver_entries())
    if (e.name == name) return e;
  throw std::invalid_argument("unknown pressure solver \"" + name + "\"");
}

std::unique_ptr<PressureSolver> make_pressure_solver(const PhysicsContext& physics) {
  return pressure_solver_entry(physics.solver).make(physics);
}

}  // namespace sph
