#pragma once
// How a floating element moves in one step: the river's surface current, the wind's drift and
// turbulent mixing.
//
// - Surface current: the depth-averaged velocity raised to the surface's by the log law,
//   u_s = u (1 + sqrt(Cf / 2) / kappa), as TELEMAC-2D's oil module does, with Manning's friction
//   Cf / 2 = g n^2 / h^(1/3) (so that the bed's shear velocity is u* = |u| sqrt(Cf / 2)).
// - Wind drift: `wind_factor` (3 %) of the 10 m wind, downwind; none under ice.
// - Mixing: a random walk with the longitudinal coefficient of Elder (1959), D_L = 5.93 h u*,
//   along the flow and the transverse one of Fischer et al. (1979) for natural streams,
//   D_T = 0.6 h u*, across it, plus the drift div(D) that keeps a well-mixed slick well mixed where
//   D varies (towards the shallows D falls to 0; without it elements would gather there). Each
//   step's displacement is one Gaussian of variance 2 D dt, so the spread does not depend on
//   the step where D is uniform. The advection is a midpoint (second-order) step, sub-stepped
//   per element so that it never crosses more than a cell of the flow's grid at once; the
//   mixing's step follows it.

#include <cstdint>
#include <functional>

#include "common/param_spec.h"
#include "farfield/flows/surface_flow.h"

namespace farfield {

struct DriftSettings {
  bool log_law = true;
  double kappa = 0.41;                // von Karman's constant
  double wind_factor = 0.03;          // of the 10 m wind
  double longitudinal_mixing = 5.93;  // D_L / (h u*), Elder
  double transverse_mixing = 0.6;     // D_T / (h u*), Fischer et al. for natural streams
  double min_diffusivity = 0;         // m^2/s added to both (0: only the bed's turbulence)
  bool mixing = true;
  double max_cells_per_substep = 1;  // the advection's Courant number on the flow's grid
  std::uint64_t seed = 1;            // set from the forecast's seed
  template <class V>
  void describe(V& v) {
    using common::param;
    v.field("log_law", log_law,
            param("", "Raise the depth-averaged velocity to the surface's by the log law"));
    v.field("kappa", kappa, param("", "Von Karman's constant").positive());
    v.field("wind_factor", wind_factor,
            param("", "Wind drift as a fraction of the 10 m wind").non_negative().at_most(0.2));
    v.field("longitudinal_mixing", longitudinal_mixing,
            param("", "D_L / (h u*): 5.93, Elder (1959)").non_negative());
    v.field("transverse_mixing", transverse_mixing,
            param("", "D_T / (h u*): 0.6, Fischer et al. (1979), natural streams").non_negative());
    v.field("min_diffusivity", min_diffusivity,
            param("m^2/s", "Added to both coefficients everywhere").non_negative());
    v.field("mixing", mixing, param("", "Random walk on (off: advection only)"));
    v.field(
        "max_cells_per_substep", max_cells_per_substep,
        param("", "Most cells of the flow's grid an element crosses in one sub-step").positive());
  }
};

struct Wind {
  double east = 0, north = 0;  // m/s, the 10 m wind's velocity (where it blows to)
};

// The surface velocity the water carries an element at (log law applied), and the mixing
// coefficients there.
struct LocalDrift {
  double u = 0, v = 0;               // m/s
  double d_along = 0, d_across = 0;  // m^2/s
  double ex = 1, ey = 0;             // unit vector along the depth-averaged flow
};
LocalDrift local_drift(const FlowSample& s, const DriftSettings& settings);

// The bed's shear velocity u* = |u| sqrt(g n^2 / h^(1/3)) (m/s) where the flow is water; 0
// elsewhere.
double shear_velocity(const FlowSample& s);

struct DriftResult {
  double x = 0, y = 0;                 // where the element ends
  double wet_x = 0, wet_y = 0;         // its last point on water at least `min_depth` deep
  FlowWhere where = FlowWhere::water;  // at (x, y): water, or a bank / outside it stopped at
};

// Whether the bank beside the water at (x, y) holds no more oil (then an element reaching it
// stays afloat and moves on along it); empty: every bank takes oil.
using BankFull = std::function<bool(double x, double y)>;

// Moves an element at (x, y) on for dt from time t (s); `step` and `element` seed its random
// walk. It stops at the first sub-step that lands on a bank that takes oil, in water shallower
// than `min_depth` (then `where` is bank) or outside the flow's domain. `grid_cell` is the
// flow's resolution (m), for the sub-steps and div(D). (spread_x, spread_y) is the step's
// displacement by the slick's spreading (m), taken with the mixing's.
DriftResult drift_element(const SurfaceFlow& flow, const DriftSettings& settings, const Wind& wind,
                          bool ice, double grid_cell, double min_depth, double t, double dt,
                          std::uint64_t step, std::uint64_t element, double x, double y,
                          const BankFull& bank_full = {}, double spread_x = 0, double spread_y = 0);

}  // namespace farfield
