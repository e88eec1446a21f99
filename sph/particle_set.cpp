#include "sph/particle_set.h"

#include <cassert>

namespace sph {

void FluidParticles::add(const Vec3& x, const Vec3& v, Real volume, Real rho0, ParticleType t) {
  // New particles are active: they go right after the last active one, so an inactive particle
  // at that slot (if any) moves to the end.
  const Index n = size();
  position.push_back(x);
  velocity.push_back(v);
  acceleration.push_back(Vec3::Zero());
  density.push_back(1);
  pressure.push_back(0);
  rest_volume.push_back(volume);
  rest_density.push_back(rho0);
  type.push_back(t);
  id.push_back(n);
  if (active != n) {
    std::swap(position[active], position[n]);
    std::swap(velocity[active], velocity[n]);
    std::swap(rest_volume[active], rest_volume[n]);
    std::swap(rest_density[active], rest_density[n]);
    std::swap(type[active], type[n]);
    std::swap(id[active], id[n]);
  }
  ++active;
}

void FluidParticles::permute(const std::vector<Index>& order) {
  assert(order.size() == active);
  std::vector<Vec3> v3;
  std::vector<Real> r;
  permute_array(position, order, v3);
  permute_array(velocity, order, v3);
  permute_array(acceleration, order, v3);
  permute_array(density, order, r);
  permute_array(pressure, order, r);
  permute_array(rest_volume, order, r);
  permute_array(rest_density, order, r);
  std::vector<ParticleType> t;
  permute_array(type, order, t);
  std::vector<Index> ids;
  permute_array(id, order, ids);
}

}  // namespace sph
