// The one place that maps a scene's `solver` name to a pressure solver.

#include <stdexcept>

#include "sph/solvers/dfsph_solver.h"
#include "sph/solvers/mtdf_solver.h"
#include "sph/solvers/pressure_solver.h"
#include "sph/solvers/wcsph_solver.h"

namespace sph {

std::vector<std::string> pressure_solver_names() {
  return {"dfsph", "mtdf", "wcsph"};
}

std::unique_ptr<PressureSolver> make_pressure_solver(const SceneConfig& scene) {
  if (scene.solver == "dfsph")
    return std::make_unique<DfsphSolver>(scene.dfsph, scene.time_step.dt_max,
                                         scene.materials.water.density);
  if (scene.solver == "mtdf") return std::make_unique<MtdfSolver>(scene);
  if (scene.solver == "wcsph")
    return std::make_unique<WcsphSolver>(scene.wcsph, scene.particle_diameter(),
                                         scene.time_step.cfl, scene.materials.water.density);
  throw std::invalid_argument("unknown pressure solver \"" + scene.solver + "\"");
}

}  // namespace sph
