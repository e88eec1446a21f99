#pragma once
// The terms the incompressible solvers of the number-density formulation share (DFSPH, IISPH,
// PBF; derivation in dfsph_solver.h). With g_ij = V_j grad W_ij (stored per pair), the boundary's
// gb_i = sum_b V_b grad W_ib and r_i = rho_ref / rho0_i:
//   the rate of change of rho/rho0:  sum_j (v_i - v_j) . g_ij + v_i . gb_i (the boundary rests);
//   the velocity change of a dt-free stiffness field s (m^2):
//       dv_i = -(r_i / dt) [ sum_j (s_i + s_j) g_ij + s_i gb_i ];
//   the diagonal of that linear map from s to the density change, 1 / alpha_i with
//       alpha_i = 1 / (r_i |sum_j g_ij + gb_i|^2 + sum_j r_j |g_ij|^2).

#include <vector>

#include "sph/core/particle_loops.h"
#include "sph/core/particle_set.h"
#include "sph/neighbours/neighbourhood.h"

namespace sph::pressure_terms {

// Rate of change of rho_i/rho0_i from the velocities v.
inline Real density_rate(Index i, const Vec3* v, const ParticleNeighbourhood& nb) {
  const Vec3 vi = v[i];
  Real rate = vi.dot(nb.boundary_gradient_sum[i]);
  const auto& ff = nb.fluid;
  for (Index k = ff.lists.offsets[i]; k < ff.lists.offsets[i + 1]; ++k)
    rate += (vi - v[ff.lists.indices[k]]).dot(ff.gradient[k]);
  return rate;
}

// ratio[i] = rho_ref / rho0_i for the first n particles (ratio is resized to the fluid's size).
inline void density_ratios(const FluidParticles& fluid, Real reference_density,
                           std::vector<Real>& ratio) {
  ratio.resize(fluid.size(), 1);
  for (Index i = 0; i < fluid.active_count(); ++i)
    ratio[i] = reference_density / fluid.rest_density[i];
}

// 1 / alpha_i: r_i |sum_j g_ij + gb_i|^2 + sum_j r_j |g_ij|^2.
inline Real factor_denominator(Index i, const ParticleNeighbourhood& nb,
                               const std::vector<Real>& ratio) {
  Vec3 grad_sum = nb.boundary_gradient_sum[i];
  Real sum_sq = 0;
  nb.fluid.for_each(i, [&](Index j, Index k) {
    const Vec3& g = nb.fluid.gradient[k];
    grad_sum += g;
    sum_sq += ratio[j] * g.squaredNorm();
  });
  return ratio[i] * grad_sum.squaredNorm() + sum_sq;
}

// First-order change of rho_i when the particles move by dx with the kernels of the positions
// before the move: sum_j g_ij . (dx_i - dx_j) + gb_i . dx_i (the boundary rests).
inline Real density_change(Index i, const ParticleNeighbourhood& nb, const std::vector<Vec3>& dx) {
  const Vec3 dxi = dx[i];
  Real change = nb.boundary_gradient_sum[i].dot(dxi);
  nb.fluid.for_each(i, [&](Index j, Index k) { change += nb.fluid.gradient[k].dot(dxi - dx[j]); });
  return change;
}

// Below this a denominator means no neighbours (alpha is then 0).
inline Real smallest_factor_denominator(const ParticleNeighbourhood& nb) {
  const Real h = nb.support_radius();
  return Real(1e-6) / (h * h);
}

// alpha[i] for the active particles (0 where a particle has no neighbours).
inline void compute_factors(const ParticleNeighbourhood& nb, const std::vector<Real>& ratio,
                            Index n, std::vector<Real>& alpha) {
  const Real tiny = smallest_factor_denominator(nb);
  for_each_particle(n, [&](Index i) {
    const Real denominator = factor_denominator(i, nb, ratio);
    alpha[i] = denominator > tiny ? Real(1) / denominator : Real(0);
  });
}

// Calls use(i, dv_i) with the velocity change of the stiffness field s, for the first n
// particles, in parallel.
template <class Use>
void stiffness_velocity_change(const ParticleNeighbourhood& nb, const std::vector<Real>& s,
                               const std::vector<Real>& ratio, Real dt, Index n, Use&& use) {
  const Real inv_dt = Real(1) / dt;
  for_each_particle(n, [&](Index i) {
    const Real si = s[i];
    Vec3 dv = si * nb.boundary_gradient_sum[i];
    const auto& ff = nb.fluid;
    for (Index k = ff.lists.offsets[i]; k < ff.lists.offsets[i + 1]; ++k)
      dv += (si + s[ff.lists.indices[k]]) * ff.gradient[k];
    use(i, Vec3(-(inv_dt * ratio[i]) * dv));
  });
}

}  // namespace sph::pressure_terms
