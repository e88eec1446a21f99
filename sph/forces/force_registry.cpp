// The one list of non-pressure forces, in the order they are applied: adding a force is its file,
// its #include and its line.

#include <algorithm>

#include "sph/forces/gravity_force.h"
#include "sph/forces/non_pressure_force.h"
#include "sph/forces/surface_tension_force.h"
#include "sph/forces/viscosity_force.h"
#include "sph/forces/xsph_force.h"
#include "sph/solvers/pressure_solver.h"

namespace sph {

std::vector<NonPressureForceEntry> non_pressure_force_entries() {
  return {
      GravityForce::entry(),
      ViscosityForce::entry(),
      SurfaceTensionForce::entry(),
      XsphForce::entry(),
  };
}

std::vector<std::unique_ptr<NonPressureForce>> make_non_pressure_forces(const SceneConfig& scene) {
  const std::vector<std::string> asked = pressure_solver_entry(scene.solver).forces;
  std::vector<std::unique_ptr<NonPressureForce>> forces;
  for (const auto& e : non_pressure_force_entries())
    if (e.wanted(scene) || std::count(asked.begin(), asked.end(), e.name) > 0)
      forces.push_back(e.make(scene));
  return forces;
}

}  // namespace sph
