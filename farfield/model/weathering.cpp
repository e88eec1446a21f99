#include "farfield/model/weathering.h"

#include <algorithm>
#include <cmath>

namespace farfield {

namespace {
constexpr double kGravity = 9.81;
constexpr double kGasConstant = 8.314;  // J/(mol K)
constexpr double kZeroCelsius = 273.15;
constexpr double kEmulsionRate = 2.02e-6;    // ADIOS-2's K0
constexpr double kLargestDroplet = 1e-5;     // m
constexpr double kSmallestDroplet = 1e-6;    // m
constexpr double kEntrainedVolume = 3.9e-8;  // m^3, Delvigne & Sweeney's lumped droplet volume
constexpr double kWaveSpeedChange = 4.433049525859078;  // m/s, where the wind stress law changes

// The wind stress factor of ADIOS-2's wave estimate.
double wind_stress(double u) {
  return u < kWaveSpeedChange ? 0.71 * std::pow(u, 1.23) : u;
}

// The wind (m/s) that would raise waves of height h over an unlimited fetch.
double wind_for_wave_height(double h) {
  const double u = std::sqrt(kGravity * h / 0.243);
  return u < kWaveSpeedChange ? std::pow(u / 0.71, 0.813008) : u;
}

// Fraction of breaking waves (Lehr & Simecek-Beatty) in fresh water, whose mean wave period is
// 2.54 s by their fit.
double breaking_fraction(double u) {
  const double period = 2.54;
  const double f = u < 4 ? 0.0125 * u / period : (0.01 * u + 0.01) / period;
  return std::min(1.0, 0.5 * f);
}
}  // namespace

double wave_height_from_wind(double wind_speed, double fetch) {
  const double ws = wind_stress(wind_speed);
  if (fetch < 2268 * ws * ws) return 0.0016 * std::sqrt(fetch / kGravity) * ws;
  return 0.243 * ws * ws / kGravity;
}

double oil_volume(const OilRecord& oil, const Elements& el, size_t e) {
  double v = 0;
  for (int c = 0; c < el.cuts; ++c)
    v += el.mass[e * size_t(el.cuts) + size_t(c)] / oil.components[size_t(c)].density;
  return v;
}

double oil_density(const OilRecord& oil, const Elements& el, size_t e) {
  const double v = oil_volume(oil, el, e);
  return v > 0 ? el.oil_mass(e) / v : oil.density;
}

namespace {
// The emulsion's kinematic viscosity (m^2/s) from the fresh oil's at the water's temperature.
double emulsion_viscosity_from(double fresh, const Elements& el, size_t e) {
  const double evaporated =
      el.released_mass[e] > 0 ? el.evaporated_mass[e] / el.released_mass[e] : 0;
  const double c = std::clamp(1500 * std::sqrt(fresh), 1.0, 10.0);
  const double y = el.water_fraction[e] / 0.84;
  return fresh * std::exp(c * evaporated) * std::pow(1 + y / (1.187 - y), 2.49);
}
}  // namespace

double emulsion_viscosity(const OilRecord& oil, const Elements& el, size_t e,
                          double temperature_c) {
  return emulsion_viscosity_from(oil.viscosity_at(temperature_c), el, e);
}

std::vector<double> evaporation_potentials(const OilRecord& oil, double temperature_c) {
  std::vector<double> k;
  const double temperature = temperature_c + kZeroCelsius;
  for (const PseudoComponent& p : oil.components)
    k.push_back(p.volatile_cut ? 1.380277 * std::cbrt(0.018 / p.molecular_weight) *
                                     p.vapour_pressure(temperature)
                               : 0.0);
  return k;
}

StepWeathering step_weathering(const OilRecord& oil, const WeatherNow& w) {
  StepWeathering s;
  s.weather = w;
  s.potentials = evaporation_potentials(oil, w.water_temperature_c);
  s.mass_transfer = w.ice ? 0.0 : 0.0048 * std::pow(std::max(w.wind_speed, 1.0), 0.78);
  double wind = w.ice ? 0.0 : w.wind_speed;
  if (w.wave_height > 0) wind = std::max(wind, wind_for_wave_height(w.wave_height));
  s.emulsion_rate = 6 * kEmulsionRate * wind * wind / kLargestDroplet;
  const double h_rms = 0.707 * w.wave_height;
  if (h_rms > 0) {
    const double energy = 0.0034 * w.water_density * kGravity * h_rms * h_rms;
    s.dispersion_rate = std::pow(energy, 0.57) * breaking_fraction(wind) * kEntrainedVolume;
  }
  s.fresh_viscosity = oil.viscosity_at(w.water_temperature_c);
  return s;
}

void evaporate(const OilRecord& oil, Elements& el, size_t e, const StepWeathering& w,
               double slick_diameter, double dt) {
  if (w.weather.ice) return;
  const std::vector<double>& k = w.potentials;
  const size_t base = e * size_t(el.cuts);
  const double temperature = w.weather.water_temperature_c + kZeroCelsius;
  const double transfer = w.mass_transfer * std::pow(std::max(slick_diameter, 1.0), -1.0 / 9);
  const double common =
      el.area[e] * (1 - el.water_fraction[e]) * transfer / (kGasConstant * temperature);
  // Per cut, k_i = Sc_i^(-2/3) P_i; the decay rate is common k_i / (sum_j m_j / MW_j).
  double moles = 0;
  for (int c = 0; c < el.cuts; ++c)
    moles += el.mass[base + size_t(c)] / oil.components[size_t(c)].molecular_weight;
  if (!(moles > 0)) return;
  // The moles' sum at mid-step, from a half step at the start's rates, so that each cut's
  // exponential over the step is second-order accurate as the light cuts leave.
  double mid_moles = 0;
  for (int c = 0; c < el.cuts; ++c)
    mid_moles += el.mass[base + size_t(c)] * std::exp(-0.5 * dt * common * k[size_t(c)] / moles) /
                 oil.components[size_t(c)].molecular_weight;
  double lost = 0;
  for (int c = 0; c < el.cuts; ++c) {
    if (k[size_t(c)] == 0) continue;
    double& m = el.mass[base + size_t(c)];
    const double kept = m * std::exp(-dt * common * k[size_t(c)] / mid_moles);
    lost += m - kept;
    m = kept;
  }
  el.evaporated_mass[e] += lost;
}

void evaporate_fingas(const OilRecord& oil, Elements& el, size_t e, const StepWeathering& w,
                      double dt) {
  if (w.weather.ice) return;
  const double target =
      oil.fingas.fraction(std::max(0.0, el.age[e] + dt), w.weather.water_temperature_c) *
      el.released_mass[e];
  double lose = target - el.evaporated_mass[e];
  const size_t base = e * size_t(el.cuts);
  for (int c = 0; c < el.cuts && lose > 0; ++c) {
    if (!oil.components[size_t(c)].volatile_cut) break;
    double& m = el.mass[base + size_t(c)];
    const double lost = std::min(m, lose);
    m -= lost;
    lose -= lost;
    el.evaporated_mass[e] += lost;
  }
}

void emulsify(const OilRecord& oil, Elements& el, size_t e, const StepWeathering& w, double dt) {
  const double y_max = oil.max_water_fraction;
  if (!(y_max > 0)) return;
  if (el.emulsion_start[e] < 0) {
    const double evaporated = el.evaporated_mass[e] / el.released_mass[e];
    if (evaporated < oil.emulsification_onset) return;
    el.emulsion_start[e] = el.age[e];
  }
  const double rate = w.emulsion_rate;
  const double s_max = 6 / kSmallestDroplet * y_max / (1 - y_max);
  double& s = el.droplet_area[e];
  s = s_max - (s_max - s) * std::exp(-rate * dt / s_max);
  el.water_fraction[e] = std::min(y_max, s * kLargestDroplet / (6 + s * kLargestDroplet));
}

double river_surface_dissipation(double depth, double shear, double water_density) {
  if (!(depth > 0) || !(shear > 0)) return 0;
  const double xi = 0.9;  // the top of the range Nezu & Nakagawa fitted
  const double profile = 9.8 / std::sqrt(xi) * std::exp(-3 * xi);
  return water_density * profile * shear * shear * shear / depth;
}

double river_dispersion_rate(double dissipation) {
  return dissipation > 0 ? std::pow(dissipation, 0.57) * kEntrainedVolume : 0.0;
}

void disperse(const OilRecord&, Elements& el, size_t e, const StepWeathering& w, double river_rate,
              double dt) {
  const double entrained = w.dispersion_rate + river_rate;
  if (!(entrained > 0)) return;
  const double nu = emulsion_viscosity_from(w.fresh_viscosity, el, e);
  const double c_roy = 2400 * std::exp(-73.682 * std::sqrt(nu));
  const double rate = c_roy * entrained * (1 - el.water_fraction[e]) * el.area[e];
  const double mass = el.oil_mass(e);
  if (!(mass > 0)) return;
  const double fraction = std::min(1.0, rate * dt / mass);
  const size_t base = e * size_t(el.cuts);
  double lost = 0;
  for (int c = 0; c < el.cuts; ++c) {
    double& m = el.mass[base + size_t(c)];
    const double kept = m * (1 - fraction);
    lost += m - kept;
    m = kept;
  }
  el.dispersed_mass[e] += lost;
}

void weather_element(const OilRecord& oil, Elements& el, size_t e, const StepWeathering& w,
                     const WeatheringSwitches& on, double slick_diameter, double river_rate,
                     double dt) {
  if (on.evaporation && on.fingas)
    evaporate_fingas(oil, el, e, w, dt);
  else if (on.evaporation)
    evaporate(oil, el, e, w, slick_diameter, dt);
  if (on.emulsification) emulsify(oil, el, e, w, dt);
  if (on.dispersion) disperse(oil, el, e, w, river_rate, dt);
}

}  // namespace farfield
