// The one list of non-pressure forces, in the order they are applied: adding a force is its file,
// its #include and its line.

#include <algorithm>

#include "sph/forces/gravity_force.h"
#include "sph/forces/non_pressure_force.h"
#include "sph/forces/surface_tension_force.h"
#include "sph/forces/viscosity_force.h"
#include "sph/forces/xsph_force.h"

namespace sph {

std::vector<NonPressureForceEntry> non_pressure_force_entries() {
  return {
      GravityForce::entry(),
      ViscosityForce::entry(),
      SurfaceTensionForce::entry(),
      XsphForce::entry(),
  };
}

std::vector<std::unique_ptr<NonPressureForce>> make_non_pressure_forces(
    const PhysicsContext& physics, const std::vector<std::string>& asked_by_solver) {
  std::vector<std::unique_ptr<NonPressureForce>> forces;
  for (const auto& e : non_pressure_force_entries())
    if (e.wanted(physics) || std::count(asked_by_solver.begin(), asked_by_solver.end(), e.name) > 0)
      forces.push_back(e.make(physics));
  return forces;
}

}  // namespace sph
