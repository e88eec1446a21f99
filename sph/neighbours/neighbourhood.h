#pragma once
// The neighbourhood of every active fluid particle (fluid and boundary neighbours, CSR) with the
// kernel value and gradient of each pair evaluated once per search. Pressure solvers iterate many
// times over the same pairs with fixed positions, so storing W_ij and grad W_ij turns each
// iteration into a gather and a dot product per pair.

#include <vector>

#include "sph/boundary/boundary.h"
#include "sph/core/kernels.h"
#include "sph/core/neighbour_grid.h"
#include "sph/core/particle_set.h"

namespace sph {

struct PairTable {
  NeighbourLists lists;
  std::vector<Real> value;     // [pairs] W(x_i - x_j)
  std::vector<Vec3> gradient;  // [pairs] V_j grad_i W(x_i - x_j), weighted by the neighbour's
                               // rest volume (fluid) or Akinci volume (boundary)

  template <class F>
  void for_each(Index i, F&& f) const {
    for (Index k = lists.offsets[i]; k < lists.offsets[i + 1]; ++k) f(lists.indices[k], k);
  }
};

// One thread's contiguous copies of a particle's pair offsets and kernel terms, which
// update_pair_kernels evaluates as SIMD.
struct PairScratch {
  std::vector<Real> dx, dy, dz, w, g;
  void fit(size_t m) {
    if (dx.size() >= m) return;
    for (auto* v : {&dx, &dy, &dz, &w, &g}) v->resize(m);
  }
};

class ParticleNeighbourhood {
 public:
  ParticleNeighbourhood(const Aabb& domain, KernelKind kernel, Real support_radius,
                        const BoundaryParticles& boundary);

  // Searches the neighbours of the active fluid particles, evaluates the kernel for every pair
  // and sets fluid.density to sum_j V_j W_ij over the particle itself and its fluid and boundary
  // neighbours: the density relative to the rest density (1 in a filled neighbourhood at rest).
  // Throws PointOutsideDomain with the index of the first particle outside the domain.
  void update(FluidParticles& fluid, const BoundaryParticles& boundary);

  // Kernel values, gradients, boundary sums and densities for the current positions, on the pairs
  // of the last update() (the same active particles, moved by a fraction of the support radius):
  // position-based solvers (PBF) correct positions several times per neighbour search.
  void update_pair_kernels(FluidParticles& fluid, const BoundaryParticles& boundary);

  // [n] sum_b V_b grad_i W_ib per fluid particle: the resting boundary enters the pressure solves
  // only through this sum, so their iterations never loop over boundary pairs.
  std::vector<Vec3> boundary_gradient_sum;

  // Active fluid indices sorted by grid cell (valid after update()).
  const std::vector<Index>& cell_order() const { return fluid_grid_.cell_order(); }

  KernelKind kernel() const { return kernel_; }
  Real support_radius() const { return support_radius_; }
  Real kernel_at_zero() const { return w_zero_; }  // W(0), a particle's own share of its sums

  PairTable fluid;     // fluid-fluid pairs
  PairTable boundary;  // fluid-boundary pairs

 private:
  KernelKind kernel_;
  Real support_radius_;
  Real w_zero_;
  std::vector<Real> boundary_volume_;  // copy of the static boundary's volumes
  std::vector<PairScratch> scratch_;   // per thread, kept between calls: no allocation per pass
  NeighbourGrid fluid_grid_;
  NeighbourGrid boundary_grid_;
};

}  // namespace sph
