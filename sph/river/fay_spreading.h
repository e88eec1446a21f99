#pragma once
// Fay's gravity-inertia spreading of oil released on still water, fitted to a slick's measured
// areas. Fay: R = k1 (Delta g V t^2)^(1/4), k1 = 1.14, so the area grows by
// pi k1^2 (Delta g V)^(1/2) per second, at a constant rate (Delta: the relative density
// difference, V: the oil volume). A slick released with a finite area A0 at t = 0 is fitted as
// A - A0 = c t^slope: Fay's law is slope 1 and k1 = sqrt(c / (pi (Delta g V)^(1/2))).
//
// The window is set by the slick, not chosen per run: it opens when the slick has grown by
// `start_growth` of its released area (the release has adjusted and the slick spreads) and
// closes when its mean thickness falls below `end_thickness_diameters` particle diameters. Below
// two diameters a particle slick is one layer plus a partial second one and cannot thin
// continuously, so its spreading is set by the resolution, not by Fay's balance.

#include <utility>
#include <vector>

#include "sph/river/slick_shape.h"

namespace sph {

struct FayWindow {
  double start_growth = 0.2;
  double end_thickness_diameters = 2.0;
};

struct FayFit {
  bool valid = false;  // at least three frames in the window
  double window_start_s = 0, window_end_s = 0;
  int frames = 0;
  double slope = 0;  // log-log slope of A - A0 against t (Fay: 1)
  double k1 = 0;     // from the least-squares rate of A - A0 against t (Fay: 1.14)
};

constexpr double kFayK1 = 1.14;

// `frames`: (t, slick shape), the first at the release; `relative_density_difference`:
// (rho_water - rho_oil) / rho_water; `gravity` in m/s^2; `diameter` the particle diameter.
FayFit fit_fay_gravity_inertia(const std::vector<std::pair<double, SlickShape>>& frames,
                               double relative_density_difference, double gravity, double diameter,
                               const FayWindow& window = {});

}  // namespace sph
