#pragma once
// Viscosity with the standard SPH Laplacian approximation of
//   Monaghan, "Smoothed particle hydrodynamics", Rep. Prog. Phys. 68 (2005), eq. 6.26 form:
//   a_i = 2 (d + 2) nu sum_j (m_j / rho_ij) (v_ij . x_ij) / (|x_ij|^2 + 0.01 h^2) grad W_ij
// with d = 3 and rho_ij = (rho_i + rho_j) / 2 (the pair's mean density, which makes the pair
// forces equal and opposite: momentum is conserved exactly, also at the free surface). The same
// term against the (resting) boundary particles, with its own coefficient, is the boundary friction
// (Akinci et al. 2012 use this form for rigid-fluid friction).

#include "sph/forces/non_pressure_force.h"

namespace sph {

class ViscosityForce : public NonPressureForce {
 public:
  // The fluid's viscosity is per particle (FluidParticles::viscosity); a pair uses the mean of
  // its two particles' values.
  explicit ViscosityForce(Real boundary_viscosity) : nu_boundary_(boundary_viscosity) {}
  // On when a phase is viscous or the boundary has friction.
  static NonPressureForceEntry entry();
  std::string name() const override { return "viscosity"; }
  void add_acceleration(FluidParticles& fluid, const BoundaryParticles& boundary,
                        const ParticleNeighbourhood& neighbourhood, Real dt) override;

 private:
  Real nu_boundary_;
};

}  // namespace sph
