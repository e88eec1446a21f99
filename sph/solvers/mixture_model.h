#pragma once
// The mixture model of MTDF-SPH for two phases, oil and water (Ren, Li, Yan, Lin, Hu,
// "Multiple-Fluid SPH Simulation Using a Mixture Model", ACM TOG 33(5), 2014).
//
// Every particle carries the oil volume fraction alpha (water has 1 - alpha); its rest density
// rho_m and viscosity are the fraction-weighted mixture. Each phase k moves relative to the
// mixture with a drift velocity u_k; we work with the drift flux J_k = alpha_k u_k:
//   J_k = tau alpha_k (rho_k - rho_c) a                        slip: buoyancy and inertia
//         - sigma (grad alpha_k - alpha_k sum_k' c_k' grad alpha_k' / alpha_k')   diffusion
//         [- tau alpha_k (grad p_k - sum_k' c_k' grad p_k')]   phase pressure (optional)
// with mass fractions c_k = alpha_k rho_k / rho_m, rho_c = sum c_k rho_k, a = g - Dv/Dt. Written
// with J the diffusion term has no 1/alpha singularity: sum_k' c_k' grad alpha_k' / alpha_k' =
// (rho_oil - rho_water) / rho_m grad alpha.
//
// The oil fraction follows D alpha / Dt = -div J_oil (the mixture velocity is divergence-free
// after the pressure solves). Each pair (i, j) exchanges oil upwind,
//   q_ij = 2 dt [max(J_i . V_j grad W_ij, 0) - max(-J_j . V_j grad W_ij, 0)],
// oil going from i to j and the same volume of water back (the first term only if i has oil and
// j water, the second only the other way round): exactly what i gives j receives, so the oil
// volume, and with it the fluid mass, is conserved to round-off. A flux limiter scales every
// exchange so that no particle gives more oil or water than it holds, which keeps alpha in
// [0, 1] without a mass-destroying clamp (the clamp that follows only removes round-off). Two
// pure particles of the same phase have nothing to exchange, so only particles at an oil-water
// interface or with a mixed composition take part: the model's cost follows the interface.
// Ren et al. clamp and renormalise small fractions, which loses mass; instead a particle left
// with a trace of a phase (below `trace_fraction`) hands it to the neighbour richest in that
// phase. Without that, diffusion leaves traces everywhere and in the collision scene 97 % of
// the particles took part; with it, 72 % (the rest of those are within a kernel radius of the
// interface, which in that shallow vessel is most of the fluid).
//
// One departure from Ren et al.: the slip is taken relative to the kernel-averaged mixture
// density around a particle, not to the particle's own mixture, so that a pure oil particle
// under water drifts up (see compute_drift).
//
// The drift momentum term -div(sum_k alpha_k rho_k u_k u_k) / rho_m is added to the
// acceleration of those particles.

#include <cstdint>
#include <vector>

#include "sph/core/particle_set.h"
#include "sph/core/physics_context.h"
#include "sph/neighbours/neighbourhood.h"

namespace sph {

// Scene key `mixture`. The mixture model of MTDF-SPH (solver `mtdf`): Ren, Li, Yan, Lin, Hu,
// "Multiple-Fluid SPH Simulation Using a Mixture Model", ACM TOG 33(5), 2014. Phases move relative
// to the mixture with drift velocities; the volume fractions follow them.
struct MixtureConfig {
  Real drift_tau = Real(1e-3);
  Real diffusion_sigma = Real(1e-4);
  bool pressure_term = false;
  Real trace_fraction = Real(1e-3);
  template <class V>
  void describe(V& v) {
    v.field("drift_tau", drift_tau,
            param("m^3 s/kg",
                  "tau of the slip term: a phase drifts at tau (rho_k - rho_c) (g - Dv/Dt) "
                  "relative to the mixture (buoyancy and inertia); larger separates faster")
                .non_negative()
                .at_most(1));
    v.field("diffusion_sigma", diffusion_sigma,
            param("m^2/s",
                  "sigma of the diffusion term: volume fractions spread down their gradients; "
                  "small keeps oil and water separate")
                .non_negative()
                .at_most(1));
    v.field("pressure_term", pressure_term,
            param("",
                  "Include Ren's phase-pressure term -tau (grad p_k - sum c_k grad p_k) with "
                  "p_k = alpha_k p; its p grad(alpha) part diffuses the phases at a rate tau p, "
                  "which at depth mixes them, so it is off by default"));
    v.field("trace_fraction", trace_fraction,
            param("",
                  "A particle holding less than this fraction of a phase hands it to the "
                  "neighbour richest in that phase after each step (volume is conserved): "
                  "Ren's clamp of small fractions without its loss of mass; 0 turns it off")
                .non_negative()
                .at_most(Real(0.1)));
  }
};

// A symmetric 3 x 3 tensor, sum_k alpha_k rho_k u_k u_k of one particle.
struct DriftStress {
  // The tensor's three columns padded to four entries (the fourth stays zero), so that its
  // product with a vector, which the drift momentum pass takes once per pair, is three packed
  // multiply-adds instead of nine scalar products.
  using Column = Eigen::Matrix<Real, 4, 1>;
  Column x = Column::Zero(), y = Column::Zero(), z = Column::Zero();
  void add_outer(const Vec3& s) {
    const Column c(s.x(), s.y(), s.z(), 0);
    x += s.x() * c;
    y += s.y() * c;
    z += s.z() * c;
  }
  Column times(const Vec3& g) const { return x * g.x() + y * g.y() + z * g.z(); }
};

class MixtureModel {
 public:
  MixtureModel(const MixtureConfig& config, const MaterialsConfig& materials, const Vec3& gravity);

  // Marks the particles that take part (mixed, or with a neighbour of another composition) and
  // computes their fraction gradients and drift fluxes. Uses fluid.pressure of the last step.
  void compute_drift(const FluidParticles& fluid, const ParticleNeighbourhood& nb);
  // Once dt is known: the oil each pair exchanges over dt, the flux limiter, and the drift
  // momentum term, added to fluid.acceleration of the particles that take part.
  void exchange_and_drift_momentum(FluidParticles& fluid, const ParticleNeighbourhood& nb, Real dt);
  // At the end of the step: applies the exchanges to the volume fractions, updates rest density,
  // viscosity and type, and records Dv/Dt of the step for the slip term of the next one.
  void transport(FluidParticles& fluid, const ParticleNeighbourhood& nb, Real dt);
  // Reorders per-particle state like FluidParticles::permute.
  void permute(const std::vector<Index>& order);

 private:
  void resize(size_t size);
  // Hands each trace of a phase (a fraction below config_.trace_fraction) to the neighbour
  // richest in that phase, so that the interface stays a few particles wide instead of a haze of
  // traces every one of which the model must visit. Volume moves between particles of equal
  // volume, so it is conserved.
  void absorb_traces(FluidParticles& fluid, const ParticleNeighbourhood& nb);
  // a = g - Dv/Dt of the last step, bounded (an impact's acceleration would otherwise drive
  // a drift of metres per second).
  Vec3 slip_acceleration(const FluidParticles& fluid, Index i) const;

  MixtureConfig config_;
  MaterialsConfig materials_;
  Vec3 gravity_;
  std::vector<Index> interface_;            // particles that take part this step
  std::vector<std::uint8_t> is_interface_;  // [n]
  std::vector<Vec3> flux_oil_;              // [n] J_oil (zero outside the interface)
  std::vector<DriftStress> drift_stress_;   // [n] sum_k alpha_k rho_k u_k u_k
  std::vector<Real> fraction_change_;       // [n] change of alpha over the step
  std::vector<Index> limited_;              // interface particles whose outflow the limiter scales
  std::vector<Real> exchange_;              // [pairs] oil moved from i to j this step
  std::vector<Real> limit_oil_;             // [n] share of its oil outflow a particle can give
  std::vector<Real> limit_water_;           // [n] same for water
  std::vector<Index> chosen_recipient_;     // [interface] where each trace goes, if anywhere
  std::vector<Vec3> step_start_velocity_;   // [n] velocity when the last step began
  std::vector<Index> step_start_id_;  // [n] whose velocity and rate these are (slots get reused)
  std::vector<Vec3> velocity_rate_;   // [n] Dv/Dt over the last step
};

}  // namespace sph
