#pragma once
// Measures of a fluid state that several validation tests check.

#include "sph/core/particle_set.h"

namespace sph::testing_support {

// Total mass of the active particles, kg: sum of rest density x rest volume.
inline double total_mass(const FluidParticles& f) {
  double m = 0;
  for (Index i = 0; i < f.active_count(); ++i)
    m += double(f.rest_density[i]) * double(f.rest_volume[i]);
  return m;
}

}  // namespace sph::testing_support
