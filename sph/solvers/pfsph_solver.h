#pragma once
// Pairwise-force SPH: Tartakovsky and Meakin, "Modeling of surface tension and contact angles
// with smoothed particle hydrodynamics", Phys. Rev. E 72 (2005) 026301, and Tartakovsky and
// Panchenko, "Pairwise force smoothed particle hydrodynamics model for multiphase flow",
// J. Comput. Phys. 305 (2016) 1119-1146.
//
// The weakly compressible pressure of WcsphSolver (its `wcsph` settings: Tait's equation, speed
// of sound, acoustic time-step limit) plus a pairwise inter-particle force between every pair of
// fluid particles within the support radius h:
//   F_ij = s_ab F(r) (x_i - x_j) / r,   F(r) = cos(3 pi r / (2 h)),
// repulsive for r < h/3 and attractive for h/3 < r < h (the 2005 paper's eq. 9). Every particle
// feels it, not only those at a surface: in the bulk the pulls cancel, where the neighbourhood is
// one-sided they add up to surface tension, and a pair strength between unlike phases below
// those of like phases (s_ow < s_ww, s_oo) makes oil and water immiscible (the 2016 paper's
// condition for separated phases). Phases are taken from the oil fraction (>= 1/2: oil). As a
// force per volume with the number-density scaling of the pressure, the acceleration is
//   a_i = (rho_ref / rho0_i) sum_j s_ab F(r_ij) (x_i - x_j) / r_ij,
// so F_ij = -F_ji for particles of equal volume and s is an acceleration (m/s^2). A fluid-wall
// strength acts the same way between fluid and boundary particles (wetting; 0: off).

#include "sph/solvers/wcsph_solver.h"

namespace sph {

// Scene key `pfsph`.
struct PfsphConfig {
  Real water_water = Real(0.2);
  Real oil_oil = Real(0.2);
  Real oil_water = Real(0.05);
  Real boundary = 0;
  template <class V>
  void describe(V& v) {
    v.field("water_water", water_water,
            param("m/s^2", "Pair strength between two water particles (cohesion of water)"));
    v.field("oil_oil", oil_oil, param("m/s^2", "Pair strength between two oil particles"));
    v.field("oil_water", oil_water,
            param("m/s^2",
                  "Pair strength between an oil and a water particle; below both like-phase "
                  "strengths the phases stay apart"));
    v.field("boundary", boundary,
            param("m/s^2", "Pair strength between fluid and boundary particles (> 0: wetting)"));
  }
};

class PfsphSolver : public WcsphSolver {
 public:
  explicit PfsphSolver(const PhysicsContext& physics);
  static PressureSolverEntry entry();
  std::string name() const override { return "pfsph"; }

 private:
  void after_non_pressure_forces(SolverHost& host, Real dt) override;

  PfsphConfig config_;
};

}  // namespace sph
