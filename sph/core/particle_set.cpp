#include "sph/core/particle_set.h"

#include <cassert>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace sph {

PhaseMix mix_phases(Real oil_fraction, Real water_density, Real water_viscosity, Real oil_density,
                    Real oil_viscosity) {
  PhaseMix m;
  m.oil_fraction = oil_fraction;
  m.rest_density = (1 - oil_fraction) * water_density + oil_fraction * oil_density;
  m.viscosity = (1 - oil_fraction) * water_viscosity + oil_fraction * oil_viscosity;
  m.type = is_oil(oil_fraction) ? ParticleType::kOil : ParticleType::kWater;
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
  for_each_array([&](const char* name, const auto& values, bool) {
    if (values.size() != position.size())
      throw std::logic_error(std::string("FluidParticles::add does not set ") + name);
  });
  if (!is_active) return;
  if (active != n) swap_slots(active, n);
  ++active;
}

void FluidParticles::swap_slots(Index a, Index b) {
  for_each_array([&](const char*, auto& values, bool) { std::swap(values[a], values[b]); });
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

void FluidParticles::set_mix(Index slot, const PhaseMix& mix) {
  oil_fraction[slot] = mix.oil_fraction;
  rest_density[slot] = mix.rest_density;
  viscosity[slot] = mix.viscosity;
  type[slot] = mix.type;
}

void FluidParticles::deactivate(Index slot) {
  assert(slot < active);
  --active;
  swap_slots(slot, active);
}

void FluidParticles::permute(const std::vector<Index>& order) {
  assert(order.size() == active);
  for_each_array([&](const char*, auto& values, bool) {
    std::remove_reference_t<decltype(values)> scratch;
    permute_array(values, order, scratch);
  });
}

}  // namespace sph
