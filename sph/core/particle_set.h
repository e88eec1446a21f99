#pragma once
// Fluid particles as a structure of arrays. Identities are fixed (`id`), while the arrays
// themselves are periodically reordered by grid cell for memory locality; writers map back to
// identity order. Active particles occupy [0, active_count()); inactive ones (not yet emitted or
// retired at an outflow) follow them and take part in nothing.

#include <vector>

#include "sph/core/types.h"

namespace sph {

// What a particle's phase composition makes of it (the mixture of Ren et al. 2014).
struct PhaseMix {
  Real oil_fraction = 0;  // volume fraction of oil; water has 1 - oil_fraction
  Real rest_density = 1000;
  Real viscosity = 0;                        // kinematic, m^2/s
  ParticleType type = ParticleType::kWater;  // the dominant phase
};

// Mixture rest density and viscosity: fraction-weighted sums over the phases.
PhaseMix mix_phases(Real oil_fraction, Real water_density, Real water_viscosity, Real oil_density,
                    Real oil_viscosity);

struct FluidParticles {
  std::vector<Vec3> position;
  std::vector<Vec3> velocity;
  std::vector<Vec3> acceleration;  // non-pressure accelerations of the current step
  std::vector<Real> density;       // rho / rho0 (dimensionless)
  std::vector<Real> pressure;      // Pa, as applied by the pressure solver in the last step
  std::vector<Real> rest_volume;   // m^3; mass = rest_density * rest_volume
  std::vector<Real> rest_density;  // kg/m^3, of the particle's phase mixture
  std::vector<Real> viscosity;     // m^2/s, kinematic, of the particle's phase mixture
  std::vector<Real> oil_fraction;  // volume fraction of oil in [0, 1]
  std::vector<ParticleType> type;
  std::vector<Index> id;  // fixed identity in [0, size())
  Index active = 0;       // number of active particles (they come first)

  // The particle record: every per-particle array, each named once. Swapping, reordering,
  // saving and loading all walk this list, so a new array is one line here (plus its value in
  // add()). `saved`: part of a saved state (the acceleration is recomputed every step).
  template <class Visit>
  void for_each_array(Visit&& visit) {
    visit_arrays(*this, visit);
  }
  template <class Visit>
  void for_each_array(Visit&& visit) const {
    visit_arrays(*this, visit);
  }

  Index size() const { return static_cast<Index>(position.size()); }
  // (rho_i + rho_j) / 2 in kg/m^3: pair terms divided by it are equal and opposite.
  Real pair_mean_density(Index i, Index j) const {
    return Real(0.5) * (rest_density[i] * density[i] + rest_density[j] * density[j]);
  }
  Index active_count() const { return active; }

  // Appends a particle; its identity is the next free number. An active one goes right after the
  // last active particle, an inactive one at the end.
  void add(const Vec3& x, const Vec3& v, Real volume, const PhaseMix& mix, bool is_active = true);
  // Slot of the inactive particle with identity `id` (a linear scan of the inactive tail).
  Index find_inactive(Index id) const;
  // Moves the inactive particle at `slot` to the end of the active range, with a new state.
  void activate(Index slot, const Vec3& x, const Vec3& v);
  // Sets the phase composition of the particle at `slot` (fraction, rest density, viscosity and
  // the dominant phase's type, together).
  void set_mix(Index slot, const PhaseMix& mix);
  // Retires the active particle at `slot`: it moves to the first inactive slot (the last active
  // one takes its place) and keeps its state and identity.
  void deactivate(Index slot);
  // Exchanges every per-particle value of two slots.
  void swap_slots(Index a, Index b);

  // Reorders every array so that new index k holds old particle order[k]. `order` must be a
  // permutation of [0, active_count()) (inactive particles keep their place).
  void permute(const std::vector<Index>& order);

 private:
  template <class Self, class Visit>
  static void visit_arrays(Self& p, Visit& visit) {
    visit("position", p.position, true);
    visit("velocity", p.velocity, true);
    visit("acceleration", p.acceleration, false);
    visit("density", p.density, true);
    visit("pressure", p.pressure, true);
    visit("rest_volume", p.rest_volume, true);
    visit("rest_density", p.rest_density, true);
    visit("viscosity", p.viscosity, true);
    visit("oil_fraction", p.oil_fraction, true);
    visit("type", p.type, true);
    visit("id", p.id, true);
  }
};

// Applies a permutation to one per-particle array: out[k] = in[order[k]] for k < order.size().
template <class T>
void permute_array(std::vector<T>& values, const std::vector<Index>& order,
                   std::vector<T>& scratch) {
  scratch.assign(values.begin(), values.end());
  for (size_t k = 0; k < order.size(); ++k) values[k] = scratch[order[k]];
}

}  // namespace sph
