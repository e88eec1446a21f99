#pragma once
// Fluid particles as a structure of arrays. Identities are fixed (`id`), while the arrays
// themselves are periodically reordered by grid cell for memory locality; writers map back to
// identity order. Active particles occupy [0, active_count()); inactive ones (not yet emitted or
// retired at an outflow) follow them and take part in nothing.

#include <vector>

#include "sph/types.h"

namespace sph {

struct FluidParticles {
  std::vector<Vec3> position;
  std::vector<Vec3> velocity;
  std::vector<Vec3> acceleration;  // non-pressure accelerations of the current step
  std::vector<Real> density;       // rho / rho0 (dimensionless)
  std::vector<Real> pressure;      // Pa, as applied by the pressure solver in the last step
  std::vector<Real> rest_volume;   // m^3; mass = rest_density * rest_volume
  std::vector<Real> rest_density;  // kg/m^3
  std::vector<ParticleType> type;
  std::vector<Index> id;  // fixed identity in [0, size())
  Index active = 0;       // number of active particles (they come first)

  Index size() const { return static_cast<Index>(position.size()); }
  Index active_count() const { return active; }

  // Appends an active particle; its identity is the next free number.
  void add(const Vec3& x, const Vec3& v, Real volume, Real rho0, ParticleType t);

  // Reorders every array so that new index k holds old particle order[k]. `order` must be a
  // permutation of [0, active_count()) (inactive particles keep their place).
  void permute(const std::vector<Index>& order);
};

// Applies a permutation to one per-particle array: out[k] = in[order[k]] for k < order.size().
template <class T>
void permute_array(std::vector<T>& values, const std::vector<Index>& order,
                   std::vector<T>& scratch) {
  scratch.assign(values.begin(), values.end());
  for (size_t k = 0; k < order.size(); ++k) values[k] = scratch[order[k]];
}

}  // namespace sph
