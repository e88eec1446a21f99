#pragma once
// What the weather does to the oil on one element over a step, as ADIOS-2 and PyGNOME do it:
//
// - Evaporation of each pseudo-component i, one exponential decay per step,
//     dm_i/dt = -A (1 - Y) K X^(-1/9) Sc_i^(-2/3) P_i(T) m_i / (R T sum_j m_j / MW_j),
//   K = 0.0048 U^0.78 (m/s, the 10 m wind U at least 1 m/s; Mackay & Matsugu), the puddle term
//   with X the diameter of the element's release's slick (at least 1 m), and the Schmidt term
//   Sc_i^(-2/3) = 1.380277 (0.018 / MW_i)^(1/3) (MW in kg/mol). None under ice.
// - Water uptake (emulsification) once the evaporated fraction reaches the oil's onset: the
//   water droplets' surface per volume of oil grows as dS/dt = k (1 - S / S_max), k = 6 K0 U^2 /
//   d_max (K0 = 2.02e-6, d_max = 1e-5 m), S_max = (6 / d_min) Y_max / (1 - Y_max) (d_min = 1e-6 m),
//   integrated exactly over each step; the water fraction is Y = min(Y_max, S d_max / (6 + S
//   d_max)). U is the wind, or the wind that would raise a given wave height if that is more.
// - Natural dispersion (Delvigne & Sweeney 1988, as ADIOS-2): Q = C_Roy D_e^0.57 f_bw V (1 - Y) A
//   kg/s, C_Roy = 2400 exp(-73.682 sqrt(nu)) with nu the emulsion's kinematic viscosity (m^2/s),
//   D_e = 0.0034 rho_w g H_rms^2 the waves' dissipated energy, f_bw the fraction of breaking
//   waves (Lehr & Simecek-Beatty) and V = 3.9e-8 m^3.
// - Natural dispersion by the river's own turbulence (an option, /environment/river_dispersion):
//   Delvigne & Hulsen (1994) carried Delvigne & Sweeney's law over to turbulence that is not
//   breaking waves, with the energy dissipation rate per unit volume eps (J m^-3 s^-1) in the
//   place of the breaking waves' D_e^0.57 f_bw: Q = C_Roy eps^0.57 V (1 - Y) A. A river's eps
//   at the surface comes from its bed shear: Nezu & Nakagawa's (1993) open-channel profile
//   eps h / u*^3 = 9.8 xi^(-1/2) exp(-3 xi) (xi = z / h), taken at the top of its range (xi =
//   0.9: 0.694 u*^3 / h), times the water's density; u* = |u| sqrt(g n^2 / h^(1/3)) as the drift
//   takes it. Added to the waves' dispersion.
// - The emulsion's properties: oil density from its components' (volumes adding), emulsion
//   density Y rho_w + (1 - Y) rho_oil; viscosity nu_0(T) exp(c F_evap) (c = 1500 sqrt(nu_0)
//   clipped to 1-10) times Mooney's (1 + (Y / 0.84) / (1.187 - Y / 0.84))^2.49.
//
// Every kilogram an element loses is added to its evaporated or dispersed mass, so the budget
// closes to rounding.

#include <vector>

#include "farfield/model/elements.h"
#include "farfield/model/oil.h"

namespace farfield {

struct WeatherNow {
  double water_temperature_c = 15;
  double wind_speed = 0;   // m/s at 10 m
  double wave_height = 0;  // m, significant
  bool ice = false;
  double water_density = 1000;  // kg/m^3
};

struct WeatheringSwitches {
  bool evaporation = true, emulsification = true, dispersion = true;
  // Evaporation by the oil's Fingas equation (OilRecord::fingas) instead of ADIOS-2's
  // pseudo-components: the element's evaporated fraction follows the equation at its age, its
  // lightest cuts going first.
  bool fingas = false;
};

// The significant wave height (m) a wind of `wind_speed` (m/s) raises over `fetch` (m), fetch
// limited as ADIOS-2 estimates it.
double wave_height_from_wind(double wind_speed, double fetch);

double oil_volume(const OilRecord& oil, const Elements& el, size_t e);   // m^3
double oil_density(const OilRecord& oil, const Elements& el, size_t e);  // kg/m^3
double emulsion_viscosity(const OilRecord& oil, const Elements& el, size_t e, double temperature_c);

// Each pseudo-component's Sc^(-2/3) P(T) (Pa) at the water's temperature (deg C): what its
// evaporation rate is proportional to, the same for every element at one moment.
std::vector<double> evaporation_potentials(const OilRecord& oil, double temperature_c);

// What one moment's weather makes the same for every element: the power laws of the wind and
// the waves, the fresh oil's viscosity and the cuts' potentials, worked out once a step rather
// than once per element.
struct StepWeathering {
  WeatherNow weather;
  std::vector<double> potentials;  // evaporation_potentials at the water's temperature
  double mass_transfer = 0;        // K = 0.0048 U^0.78 (m/s; 0 under ice)
  double emulsion_rate = 0;        // k = 6 K0 U^2 / d_max (1/s per m^2/m^3 of droplet surface)
  double dispersion_rate = 0;      // D_e^0.57 f_bw V (0 without waves): Q / (C_Roy (1 - Y) A)
  double fresh_viscosity = 0;      // m^2/s at the water's temperature
};
StepWeathering step_weathering(const OilRecord& oil, const WeatherNow& w);

// Evaporates element e for dt with its slick's diameter `slick_diameter` (m).
void evaporate(const OilRecord& oil, Elements& el, size_t e, const StepWeathering& w,
               double slick_diameter, double dt);
// Evaporates element e to its Fingas fraction at age + dt, lightest cuts first.
void evaporate_fingas(const OilRecord& oil, Elements& el, size_t e, const StepWeathering& w,
                      double dt);
void emulsify(const OilRecord& oil, Elements& el, size_t e, const StepWeathering& w, double dt);
// The turbulence's dissipation rate per unit volume (J m^-3 s^-1) at a river's surface, from its
// depth (m), the bed's shear velocity (m/s; drift.h's shear_velocity) and the water's density.
double river_surface_dissipation(double depth, double shear_velocity, double water_density);
// D&H's eps^0.57 V for that dissipation: what disperse() adds to the waves' dispersion_rate.
double river_dispersion_rate(double dissipation);

// Disperses element e for dt at the waves' rate plus `river_rate` (river_dispersion_rate).
void disperse(const OilRecord& oil, Elements& el, size_t e, const StepWeathering& w,
              double river_rate, double dt);

// All three, as switched; `river_rate` as disperse() takes it.
void weather_element(const OilRecord& oil, Elements& el, size_t e, const StepWeathering& w,
                     const WeatheringSwitches& on, double slick_diameter, double river_rate,
                     double dt);

}  // namespace farfield
