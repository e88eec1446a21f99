#include "sph/forces/gravity_force.h"
#include "sph/forces/non_pressure_force.h"
#include "sph/forces/surface_tension_force.h"
#include "sph/forces/viscosity_force.h"
#include "sph/forces/xsph_force.h"

namespace sph {

std::vector<std::unique_ptr<NonPressureForce>> make_non_pressure_forces(const SceneConfig& scene) {
  std::vector<std::unique_ptr<NonPressureForce>> forces;
  forces.push_back(std::make_unique<GravityForce>(scene.gravity));
  const MaterialsConfig& m = scene.materials;
  if (m.water.viscosity > 0 || m.oil.viscosity > 0 || scene.boundary.friction > 0)
    forces.push_back(std::make_unique<ViscosityForce>(scene.boundary.friction));
  // Surface tension belongs to MTDF-SPH: plain DFSPH on the same scene is the comparison.
  if (scene.solver == "mtdf")
    forces.push_back(std::make_unique<SurfaceTensionForce>(
        scene.surface_tension, scene.particle_diameter(), scene.support_radius(),
        scene.materials.water.density));
  if (scene.xsph > 0) forces.push_back(std::make_unique<XsphForce>(scene.xsph));
  return forces;
}

}  // namespace sph
