#include "sph/particle_set.h"

#include <cassert>

namespace sph {

PhaseMix mix_phases(Real oil_fraction, Real water_density, Real water_viscosity, Real oil_density,
                    Real oil_viscosity) {
  PhaseMix m;
  m.oil_fraction = oil_fraction;
  m.rest_density = (1 - oil_fraction) * water_density + oil_fraction * oil_density;
  m.viscosity = (1 - oil_fraction) * water_viscosity + oil_fraction * oil_viscosity;
  m.type = oil_fraction > Real(0.5) ? ParticleType::kOil : ParticleType::kWater;
  return m;
}

void FluidParticles::add(const Vec3& x, const Vec3& v, Real volume, const PhaseMix& mix) {
  // New particles are active: they go right after the last active one, so an inactive particle
  // at that slot (if any) moves to the end.
  const Index n = size();
  position.push_back(x);
  velocity.push_back(v);
  acceleration.push_back(Vec3::Zero());
  density.push_back(1);
  pressure.push_back(0);
  rest_volume.push_back(volume);
  rest_density.push_back(mix.rest_density);
  viscosity.push_back(mix.viscosity);
  oil_fraction.push_back(mix.oil_fraction);
  type.push_back(mix.type);
  id.push_back(n);
  if (active != n) {
    std::swap(position[active], position[n]);
    std::swap(velocity[active], velocity[n]);
    std::swap(rest_volume[active], rest_volume[n]);
    std::swap(rest_density[active], rest_density[n]);
    std::swap(viscosity[active], viscosity[n]);
    std::swap(oil_fraction[active], oil_fraction[n]);
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
  permute_array(viscosity, order, r);
  permute_array(oil_fraction, order, r);
  std::vector<ParticleType> t;
  permute_array(type, order, t);
  std::vector<Index> ids;
  permute_array(id, order, ids);
}

}  // namespace sph
