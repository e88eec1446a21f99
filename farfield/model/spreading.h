#pragma once
// Fay's gravity-viscous spreading of a release's slick, with PyGNOME's FayGravityViscous
// constants (k1 = 1.53, k2 = 1.21, k_nu = 1.45; water's kinematic viscosity 1e-6 m^2/s):
//   relative buoyancy   Delta = (rho_w - rho_oil) / rho_w
//   initial area        A0 = pi k2^4 / k1^2 (V0^5 g Delta / nu_w^2)^(1/6), reached at
//                       t0 = (k2 / k1)^4 (V0 / (nu_w g Delta))^(1/3)
//   then                dA/dt = C^2 / (2 A), C = pi k_nu^2 (V0^2 g Delta / sqrt(nu_w))^(1/3),
//                       i.e. A = C sqrt(t), Fay's gravity-viscous law, once A >> A0,
// integrated exactly: A(t) = sqrt(A0^2 + C^2 (t - t0)) for t > t0. V0 is the oil released by
// the element's release in the step it was born in; the element covers its share of the slick's
// area, and stops spreading at the oil's minimum thickness (OilRecord::min_thickness).

namespace farfield {

struct FaySlick {
  double initial_area = 0;  // m^2
  double onset = 0;         // s: t0
  double rate = 0;          // m^2/s^(1/2): C
  double area_at(double age) const;
};

// Throws std::invalid_argument when the oil is not lighter than the water.
FaySlick fay_slick(double volume, double oil_density, double water_density);

}  // namespace farfield
