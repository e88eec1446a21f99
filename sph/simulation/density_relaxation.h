#pragma once
// Moves the particles of a frame that no solver made (a learned simulator's prediction) back
// towards rest density with DFSPH's own constant-density correction: per iteration a neighbour
// search on the given positions (boundary included), the factors alpha_i, the stiffness
// s_i = max(rho_i/rho0 - 1, 0) alpha_i and the position change
//   dx_i = -r_i [sum_j V_j (s_i + s_j) grad W_ij + sum_b V_b s_i grad W_ib],
// which is DFSPH's velocity change times dt (it is dt-free: the correction a step of any length
// would make to positions). No advection, no forces: after Toshev et al. 2024, "Neural SPH",
// learned rollouts drift into clusters and voids that no SPH state has, and a few such iterations
// remove the compression. Only compression is corrected (a free surface has a density deficit
// that is not an error), as in the solver.

#include <vector>

#include "sph/boundary/boundary.h"
#include "sph/neighbours/neighbourhood.h"
#include "sph/scene/scene.h"
#include "sph/simulation/simulation.h"

namespace sph {

// Distribution of the compression max(rho/rho0 - 1, 0) over the particles inside the domain.
struct CompressionStats {
  double mean = 0, p95 = 0, max = 0;
  long particles = 0;
};

class DensityRelaxation {
 public:
  explicit DensityRelaxation(const SceneConfig& scene);
  // Corrects `positions` (m) of fluid particles with oil fractions `oil_fraction` by
  // `iterations` iterations; particles outside the scene's domain are left where they are.
  // Returns the compression before the first iteration and after the last.
  std::pair<CompressionStats, CompressionStats> relax(std::vector<Vec3>& positions,
                                                      const std::vector<Real>& oil_fraction,
                                                      int iterations);
  // The compression of a frame without moving it.
  CompressionStats measure(const std::vector<Vec3>& positions,
                           const std::vector<Real>& oil_fraction);

 private:
  // The particles inside the domain as a particle set with densities; `inside` their indices.
  FluidParticles fluid_of(const std::vector<Vec3>& positions, const std::vector<Real>& oil_fraction,
                          std::vector<size_t>& inside);
  CompressionStats compression(const FluidParticles& fluid) const;

  Simulation reference_;  // the scene, its boundary, domain and kernel
  Real volume_;
  ParticleNeighbourhood neighbourhood_;
  std::vector<Real> ratio_, alpha_, s_;
};

}  // namespace sph
