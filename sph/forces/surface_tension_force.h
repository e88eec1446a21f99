#pragma once
// Modified cosine-force surface tension of MTDF-SPH. Between two particles at distance r within
// the support radius h the pair force is
//   F_ij = s_ij cos(3 pi r / (2 h)) W(r) (x_i - x_j) / r,
// repulsive for r < h/3 and attractive for h/3 < r < h (the cosine law of Tartakovsky & Meakin,
// Phys. Rev. E 72, 2005, weighted by the kernel so that it fades smoothly at the support's
// edge). s_ij is `like` between particles of one phase (cohesion), `unlike` between oil and
// water (negative: the phases push each other away at the pair distance, which keeps their
// interface sharp) and `boundary` between fluid and wall (wetting). We scale it as a force per
// volume: a_i = sum_j s_ij (rho_ref / rho0_i) V_j cos(...) W (x_i - x_j) / r, so that s is an
// acceleration and F_ij = -F_ji.
//
// Inside a fluid of one phase the pulls cancel; they only act where the neighbourhood is
// one-sided. With `surface_only` (the paper's choice) the force is evaluated for particles at
// the free surface (fewer neighbours than a fraction of a full neighbourhood) or at the oil-water
// interface (a neighbour of the other phase) and the rest skip the cosine entirely.

#include <vector>

#include "sph/forces/non_pressure_force.h"

namespace sph {

// Scene key `surface_tension`. The pair force
// s cos(3 pi r / (2 h)) W(r) along x_i - x_j (repulsive for r < h/3, attractive beyond), with a
// strength s for like phases, unlike phases and fluid-boundary pairs (wetting).
struct SurfaceTensionConfig {
  Real like = 20;
  Real unlike = -20;
  Real boundary = 0;
  bool surface_only = true;
  Real surface_neighbour_fraction = Real(0.8);
  template <class V>
  void describe(V& v) {
    v.field("like", like,
            param("m/s^2", "Strength s between particles of the same phase (> 0: cohesion)"));
    v.field("unlike", unlike,
            param("m/s^2",
                  "Strength s between oil and water (< 0: repulsion at the pair distance, which "
                  "keeps the phases apart)"));
    v.field("boundary", boundary,
            param("m/s^2", "Strength s between fluid and boundary (> 0: wetting)"));
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
  Index surface_neighbour_count_;  // fewer neighbours than this: a free-surface particle
  std::vector<Real> law_;
  Real law_scale_ = 0;  // table intervals per m^2 of r^2
  KernelKind law_kernel_ = KernelKind::kCubicSpline;
  Real law_support_radius_ = 0;
};

}  // namespace sph
