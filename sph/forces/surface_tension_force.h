#pragma once
// Modified cosine-force surface tension of MTDF-SPH. Between two particles at distance r within
// the support radius h the pair force is
//   F_ij = s_ij cos(3 pi r / (2 h)) W(r) (x_i - x_j) / r,
// repulsive for r < h/3 and attractive for h/3 < r < h (the cosine law of Tartakovsky & Meakin,
// Phys. Rev. E 72, 2005, weighted by the kernel so that it fades smoothly at the support's
// edge). s_ij depends on the phases of i and j (oil when the oil fraction is at least 1/2) and is
// derived from physical interfacial tensions and the particle size (pair_strengths below), so a
// change of resolution keeps the physics; `boundary` is the strength between fluid and wall
// (wetting). We scale it as a force per volume: a_i = sum_j s_ij (rho_ref / rho0_i) V_j cos(...)
// W (x_i - x_j) / r, so that s is an acceleration and F_ij = -F_ji.
//
// Derivation of the tensions: the pair force between particles of volume V is
// F(r) = rho_ref s V^2 cos(3 pi r / 2h) W(r), with the potential phi(r) = int_r^h F. Splitting a
// lattice of one phase across a plane breaks the pairs across it; the work per unit area is
// twice the surface tension (two surfaces): sigma = -(1 / 2A) sum_cross phi = lambda s, with
// lambda summed over the lattice (tension_per_strength). For two phases the work of adhesion is
// 2 lambda s_ab, so sigma_ab = sigma_a + sigma_b - 2 lambda s_ab (Tartakovsky & Panchenko,
// J. Comput. Phys. 305, 2016, for pairwise forces). With water's 0.072 N/m at 4 cm particles
// s is about 0.05 m/s^2: surface tension is far weaker than gravity at that size (the capillary
// length is 2.7 mm), as in nature, and a slick spreads by gravity down to one particle.
//
// Inside a fluid of one phase the pulls cancel; they only act where the neighbourhood is
// one-sided. With `surface_only` (the paper's choice) the force is evaluated for particles at
// the free surface (fewer neighbours than a fraction of a full neighbourhood) or at the oil-water
// interface (a neighbour of the other phase) and the rest skip the cosine entirely.

#include <vector>

#include "sph/core/kernels.h"
#include "sph/forces/non_pressure_force.h"

namespace sph {

// Scene key `surface_tension`: the three interfacial tensions of water, oil and air, in N/m, from
// which the pair strengths follow (see SurfaceTensionForce), and a raw fluid-wall strength.
// Defaults: water/air 0.072 N/m at 20 C; a medium crude's oil/air 0.030 and oil/water 0.025 N/m,
// whose spreading coefficient S = 0.072 - 0.030 - 0.025 = +0.017 N/m makes it spread on water.
struct SurfaceTensionConfig {
  Real water_air = Real(0.072);
  Real oil_air = Real(0.030);
  Real oil_water = Real(0.025);
  Real boundary = 0;
  bool surface_only = true;
  Real surface_neighbour_fraction = Real(0.8);
  template <class V>
  void describe(V& v) {
    v.field("water_air", water_air,
            param("N/m", "Interfacial tension of water and air (the free surface)").positive());
    v.field("oil_air", oil_air, param("N/m", "Interfacial tension of oil and air").positive());
    v.field("oil_water", oil_water,
            param("N/m",
                  "Interfacial tension of oil and water. Oil spreads on water when the spreading "
                  "coefficient water_air - oil_air - oil_water is positive, and gathers into a "
                  "lens when it is negative")
                .non_negative());
    v.field("boundary", boundary,
            param("m/s^2", "Pair strength s between fluid and boundary (> 0: wetting)"));
    v.field("surface_only", surface_only,
            param("",
                  "Apply the force to free-surface and oil-water interface particles only (as "
                  "the MTDF-SPH paper does); false: to every particle"));
    v.field("surface_neighbour_fraction", surface_neighbour_fraction,
            param("",
                  "A particle with fewer neighbours than this fraction of a full neighbourhood "
                  "is at the free surface")
                .positive()
                .at_most(1));
  }
};

// The pair strengths s (m/s^2) of the cosine force for water-water, oil-oil and oil-water pairs.
struct PairStrengths {
  Real water = 0, oil = 0, oil_water = 0;
};

// The tension of a flat free surface of a particle lattice per unit pair strength, lambda in
// (N/m) / (m/s^2): the work of pulling the lattice apart across a plane, per unit area, halved
// (two surfaces), for the kernel, support radius h, lattice spacing and particle volume.
Real tension_per_strength(KernelKind kernel, Real support_radius, Real spacing, Real volume,
                          Real reference_density);

// Strengths that give the configured tensions: with air as empty space, a pairwise force gives
// sigma_phase_air = lambda s_phase and sigma_oil_water = lambda (s_water + s_oil - 2 s_oil_water),
// so s_water = sigma_wa / lambda, s_oil = sigma_oa / lambda and s_oil_water = (sigma_wa +
// sigma_oa - sigma_ow) / (2 lambda). Oil spreads (S > 0) exactly when s_oil_water > s_oil.
PairStrengths pair_strengths(const SurfaceTensionConfig& config, Real lambda);

class SurfaceTensionForce : public NonPressureForce {
 public:
  SurfaceTensionForce(const SurfaceTensionConfig& config, Real particle_spacing,
                      Real support_radius, Real reference_density);
  // Only on when the pressure solver asks for it (MTDF-SPH): plain DFSPH on the same scene is
  // the comparison.
  static NonPressureForceEntry entry();
  std::string name() const override { return "surface_tension"; }
  void add_acceleration(FluidParticles& fluid, const BoundaryParticles& boundary,
                        const ParticleNeighbourhood& neighbourhood, Real dt) override;

 private:
  // The pair law cos(3 pi r / 2h) W(r) / r as a table over (r / h)^2, made for the kernel and
  // support radius of the first neighbourhood it sees (and remade if they change).
  void tabulate_pair_law(KernelKind kernel, Real support_radius);

  SurfaceTensionConfig config_;
  Real reference_density_;
  Real spacing_;
  Index surface_neighbour_count_;  // fewer neighbours than this: a free-surface particle
  std::vector<Real> law_;
  Real law_scale_ = 0;       // table intervals per m^2 of r^2
  PairStrengths strengths_;  // from the tensions, for the kernel and support of the table
  KernelKind law_kernel_ = KernelKind::kCubicSpline;
  Real law_support_radius_ = 0;
};

}  // namespace sph
