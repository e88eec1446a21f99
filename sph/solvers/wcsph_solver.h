#pragma once
// Weakly compressible SPH, Becker & Teschner, "Weakly compressible SPH for free surface flows",
// SCA 2007: Tait's equation p = B ((rho/rho0)^gamma - 1), B = rho0 c^2 / gamma (eq. 7), with the
// symmetric pressure force (eq. 6) and boundary pressure mirroring (Akinci et al. 2012, eq. 10).
// Negative pressures are clamped to zero so the free surface does not stick together. The speed
// of sound c = sound_speed_factor x expected_max_velocity also limits the time step (acoustic CFL
// dt <= cfl * 0.4 * diameter / c). Phases of different rest density use the number-density
// form of Solenthaler & Pajarola 2008 as in DfsphSolver: Tait's equation in rho/rho0 with the
// reference (water) stiffness, accelerations scaled by rho_ref / rho0_i.

#include "sph/solvers/pressure_solver.h"

namespace sph {

// Scene key `wcsph`.
struct WcsphConfig {
  Real stiffness_exponent = 7;
  Real expected_max_velocity = 5;
  Real sound_speed_factor = 10;
  template <class V>
  void describe(V& v) {
    v.field("stiffness_exponent", stiffness_exponent,
            param("", "Exponent gamma of Tait's equation").at_least(1).at_most(10));
    v.field("expected_max_velocity", expected_max_velocity,
            param("m/s", "Largest flow speed expected; sets the speed of sound").positive());
    v.field("sound_speed_factor", sound_speed_factor,
            param("",
                  "Speed of sound = this x expected_max_velocity (10 keeps density "
                  "fluctuations near 1 %)")
                .at_least(1));
  }
};

class WcsphSolver : public PressureSolver {
 public:
  WcsphSolver(const WcsphConfig& config, Real particle_diameter, Real cfl, Real reference_density);
  static PressureSolverEntry entry();
  std::string name() const override { return "wcsph"; }
  void step(SolverHost& host, StepStats& stats) override;
  void permute(const std::vector<Index>&) override {}  // no state kept between steps

 protected:
  // Where a solver built on WCSPH (PF-SPH) adds accelerations: after the non-pressure forces of
  // step dt, before the pressure acceleration and the integration.
  virtual void after_non_pressure_forces(SolverHost&, Real /*dt*/) {}
  Real reference_density() const { return reference_density_; }  // rho_ref (water)

 private:
  WcsphConfig config_;
  Real sound_speed_;
  Real acoustic_dt_limit_;
  Real reference_density_;
};

}  // namespace sph
