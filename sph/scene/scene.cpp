#include "sph/scene/scene.h"

#include "sph/core/lattice.h"

namespace sph {

PhysicsContext SceneConfig::physics() const {
  PhysicsContext p;
  p.solver = solver;
  p.kernel = kernel_kind(kernel);
  p.particle_radius = particle_radius;
  p.support_radius = support_radius();
  p.gravity = gravity;
  p.time_step = time_step;
  p.materials = materials;
  p.boundary_friction = boundary.friction;
  p.xsph = xsph;
  p.sections = sections;
  return p;
}

Real particle_rest_volume(const SceneConfig& scene) {
  return lattice_rest_volume(kernel_kind(scene.kernel), scene.support_radius(),
                             scene.particle_diameter());
}

std::vector<HeightFieldConfig> boundary_height_fields(const SceneConfig& scene) {
  std::vector<HeightFieldConfig> fields = scene.height_fields;
  if (scene.terrain_grid) {
    const Terrain& t = *scene.terrain_grid;
    HeightFieldConfig field;
    field.origin = Vec3(t.origin_x, t.origin_y, 0);
    field.cell_size = t.cell_size;
    field.heights.assign(size_t(t.ny), std::vector<Real>(size_t(t.nx)));
    for (int iy = 0; iy < t.ny; ++iy)
      for (int ix = 0; ix < t.nx; ++ix) field.heights[size_t(iy)][size_t(ix)] = t.at(ix, iy);
    fields.push_back(std::move(field));
  }
  return fields;
}

}  // namespace sph
