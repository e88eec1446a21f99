#include "sph/core/particle_set.h"

#include <cassert>
#include <stdexcept>
#include <string>

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

void FluidParticles::add(const Vec3& x, const Vec3& v, Real volume, const PhaseMix& mix,
                         bool is_active) {
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
  if (!is_active) return;
  if (active != n) swap_slots(active, n);
  ++active;
}

void FluidParticles::swap_slots(Index a, Index b) {
  std::swap(position[a], position[b]);
  std::swap(velocity[a], velocity[b]);
  std::swap(acceleration[a], acceleration[b]);
  std::swap(density[a], density[b]);
  std::swap(pressure[a], pressure[b]);
  std::swap(rest_volume[a], rest_volume[b]);
  std::swap(rest_density[a], rest_density[b]);
  std::swap(viscosity[a], viscosity[b]);
  std::swap(oil_fraction[a], oil_fraction[b]);
  std::swap(type[a], type[b]);
  std::swap(id[a], id[b]);
}

Index FluidParticles::find_inactive(Index wanted) const {
  for (Index slot = active; slot < size(); ++slot)
    if (id[slot] == wanted) return slot;
  throw std::logic_error("particle " + std::to_string(wanted) + " is not inactive");
}

void FluidParticles::activate(Index slot, const Vec3& x, const Vec3& v) {
  assert(slot >= active && slot < size());
  swap_slots(slot, active);
  position[active] = x;
  velocity[active] = v;
  acceleration[active].setZero();
  density[active] = 1;
  pressure[active] = 0;
  ++active;
}

void FluidParticles::deactivate(Index slot) {
  assert(slot < active);
  --active;
  swap_slots(slot, active);
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
