#include "farfield/model/far_field_model.h"

#include <algorithm>
#include <cmath>

#include "farfield/model/random_stream.h"

namespace farfield {

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr std::uint64_t kRefloatSalt = 0x5EF1'0A7ull;
// Element e's place in the unit disc, uniform over it: Roberts' R2 low-discrepancy sequence
// (the plastic number's powers) mapped to the disc, so that any run of consecutive elements, a
// slick's, covers it evenly without the clumps of random draws.
void place_in_disc(std::uint64_t e, double& ux, double& uy) {
  constexpr double a1 = 0.7548776662466927, a2 = 0.5698402909980532;
  const double u = std::fmod(0.5 + a1 * double(e), 1.0), v = std::fmod(0.5 + a2 * double(e), 1.0);
  const double r = std::sqrt(u), theta = 2 * kPi * v;
  ux = r * std::cos(theta);
  uy = r * std::sin(theta);
}
}  // namespace

double Budget::closure_error() const {
  if (!(released > 0)) return 0;
  return std::abs(released - (floating + stranded + evaporated + dispersed + left_reach + sunk)) /
         released;
}

FarFieldModel::FarFieldModel(FarFieldSetup setup) : setup_(std::move(setup)) {
  elements_.cuts = int(setup_.oil.components.size());
  released_.assign(setup_.releases.size(), ReleaseProgress{});
  bank_held_.assign(size_t(setup_.banks.bins()), 0.0);
}

double FarFieldModel::emulsion_volume(size_t e) const {
  return oil_volume(setup_.oil, elements_, e) / (1 - elements_.water_fraction[e]);
}

namespace {

// Element k of n of a release: when it is born (s) and the oil it carries (m^3). Elements are
// born evenly over the release, each carrying the oil released in its slot of the time.
double birth_time(const ReleaseSpec& r, int k) {
  if (!(r.end > r.start)) return r.start;
  return r.start + (k + 0.5) * (r.end - r.start) / r.elements;
}
double element_volume(const ReleaseSpec& r, int k) {
  if (!(r.end > r.start)) return r.rate.at(r.start) / r.elements;
  const double slot = (r.end - r.start) / r.elements;
  return r.rate.integral(r.start + k * slot, r.start + (k + 1) * slot);
}
long slick_interval_of(const ReleaseSpec& r, int k, double interval) {
  return long(std::floor((birth_time(r, k) - r.start) / interval));
}

}  // namespace

void FarFieldModel::start_slick(size_t i, int k, long interval) {
  const ReleaseSpec& r = setup_.releases[i];
  double volume = 0;
  for (int j = k; j < r.elements && slick_interval_of(r, j, setup_.slick_interval) == interval; ++j)
    volume += element_volume(r, j);
  ReleaseProgress& p = released_[i];
  p.interval = interval;
  p.slick_volume = volume;
  p.slick = -1;
  if (!(volume > 0)) return;
  slicks_.push_back(fay_slick(volume, setup_.oil.density, setup_.environment.water_density));
  p.slick = int(slicks_.size()) - 1;
}

void FarFieldModel::release(double t0, double t1) {
  const OilRecord& oil = setup_.oil;
  std::vector<double> cuts(oil.components.size());
  for (size_t i = 0; i < setup_.releases.size(); ++i) {
    const ReleaseSpec& r = setup_.releases[i];
    ReleaseProgress& p = released_[i];
    while (p.born < r.elements) {
      const int k = p.born;
      const double t = birth_time(r, k);
      if (t >= t1) break;
      ++p.born;
      const long interval = slick_interval_of(r, k, setup_.slick_interval);
      if (interval != p.interval) start_slick(i, k, interval);
      const double volume = element_volume(r, k);
      if (!(volume > 0) || p.slick < 0) continue;
      const double mass = volume * oil.density;
      for (size_t c = 0; c < cuts.size(); ++c) cuts[c] = mass * oil.components[c].mass_fraction;
      const double share = volume / p.slick_volume;
      const double min_thickness = oil.min_thickness(setup_.environment.water_temperature_c.at(t));
      const double area =
          std::min(share * slicks_[size_t(p.slick)].initial_area, volume / min_thickness);
      const double along = r.elements > 1 ? (k + 0.5) / r.elements : 0.0;
      const double x = r.x0 + along * (r.x1 - r.x0), y = r.y0 + along * (r.y1 - r.y0);
      // Born at t, inside this step: a negative age until the step's start catches up.
      elements_.add(x, y, cuts, area, p.slick, share, time_ - std::max(t, t0));
    }
  }
}

void FarFieldModel::add_parcel(double x, double y, double mass, double area, int elements) {
  const OilRecord& oil = setup_.oil;
  std::vector<double> cuts(oil.components.size());
  for (size_t c = 0; c < cuts.size(); ++c)
    cuts[c] = mass / elements * oil.components[c].mass_fraction;
  slicks_.push_back(fay_slick(mass / oil.density, oil.density, setup_.environment.water_density));
  for (int k = 0; k < elements; ++k)
    elements_.add(x, y, cuts, area / elements, int(slicks_.size()) - 1, 1.0 / elements, 0.0);
}

void FarFieldModel::step(double dt) {
  const double t0 = time_, t1 = time_ + dt;
  release(t0, t1);
  const Environment& env = setup_.environment;
  const WeatherNow weather = env.weather_at(t0 + 0.5 * dt);
  const Wind wind = env.wind_at(t0 + 0.5 * dt);
  const double min_thickness = setup_.oil.min_thickness(weather.water_temperature_c);
  const StepWeathering weathering = step_weathering(setup_.oil, weather);
  const SurfaceFlow& flow = *setup_.flow;
  const double cell = flow.resolution();
  const long n = long(elements_.size());
  moved_.resize(size_t(n));
  Elements& el = elements_;

  // Weathering, spreading and drift of every floating element, side by side.
#pragma omp parallel for schedule(static)
  for (long i = 0; i < n; ++i) {
    const size_t e = size_t(i);
    if (el.state[e] != ElementState::floating) continue;
    // An element born inside this step lives only its remainder.
    const double live = std::min(dt, dt + el.age[e]);
    const FaySlick& slick = slicks_[size_t(el.slick[e])];
    const double share = el.slick_share[e];
    const double slick_diameter = 2 * std::sqrt(el.area[e] / share / kPi);
    double river_rate = 0;
    if (env.river_dispersion && setup_.weathering.dispersion) {
      const FlowSample s = flow.sample(el.x[e], el.y[e], t0);
      river_rate = river_dispersion_rate(
          river_surface_dissipation(s.depth, shear_velocity(s), env.water_density));
    }
    weather_element(setup_.oil, el, e, weathering, setup_.weathering, slick_diameter, river_rate,
                    live);
    el.age[e] += dt;
    // Weathered as dense as the water it floats on, the oil goes down where it is.
    if (env.sinking && oil_density(setup_.oil, el, e) >= env.water_density) {
      el.state[e] = ElementState::sunk;
      continue;
    }
    double spread_x = 0, spread_y = 0;
    if (setup_.spreading) {
      const double most = el.released_mass[e] / setup_.oil.density / min_thickness;
      el.area[e] = std::max(el.area[e], std::min(share * slick.area_at(el.age[e]), most));
      // The slick's elements fill its disc: each moves out to its own place in it as the
      // radius grows, so that the mapped slick is the area the weathering uses.
      const double radius = std::sqrt(el.area[e] / share / kPi);
      double ux, uy;
      place_in_disc(std::uint64_t(e), ux, uy);
      spread_x = (radius - el.spread_radius[e]) * ux;
      spread_y = (radius - el.spread_radius[e]) * uy;
      el.spread_radius[e] = radius;
    }
    const double volume = emulsion_volume(e);
    const double min_depth = std::max(setup_.dry_depth, volume / el.area[e]);  // its thickness
    // A bank bin that cannot take this element turns it away (the bins are only read while the
    // elements drift side by side; the stranding below checks again in element order).
    const BankFull bank_full = [this, volume](double x, double y) {
      const int bin = setup_.banks.bin_at(setup_.centreline.locate(x, y));
      return bank_held_[size_t(bin)] + volume > setup_.banks.capacity_m3(bin);
    };
    moved_[e] = drift_element(flow, setup_.drift, wind, env.ice, cell, min_depth, t1 - live, live,
                              std::uint64_t(steps_), std::uint64_t(e), el.x[e], el.y[e], bank_full,
                              spread_x, spread_y);
  }

  // Stranding and leaving, in element order (the banks' capacity is shared).
  for (size_t e = 0; e < size_t(n); ++e) {
    if (el.state[e] != ElementState::floating) continue;
    const DriftResult& r = moved_[e];
    if (r.where == FlowWhere::water) {
      el.x[e] = r.x;
      el.y[e] = r.y;
    } else if (r.where == FlowWhere::outside) {
      el.x[e] = r.x;
      el.y[e] = r.y;
      el.state[e] = ElementState::left_reach;
    } else {
      el.x[e] = r.wet_x;
      el.y[e] = r.wet_y;
      const int bin = setup_.banks.bin_at(setup_.centreline.locate(r.wet_x, r.wet_y));
      const double volume = emulsion_volume(e);
      if (bank_held_[size_t(bin)] + volume <= setup_.banks.capacity_m3(bin)) {
        bank_held_[size_t(bin)] += volume;
        el.state[e] = ElementState::stranded;
        el.bank_segment[e] = bin;
        el.stranded_since[e] = t1;
      }
    }
  }

  // Stranded oil floats off at its bank's rate.
  for (size_t e = 0; e < size_t(n); ++e) {
    if (el.state[e] != ElementState::stranded || el.stranded_since[e] >= t1) continue;
    const int bin = el.bank_segment[e];
    const double p = 1 - std::exp2(-dt / setup_.banks.class_of(bin).refloat_half_life_s);
    CounterRandom random(setup_.drift.seed, std::uint64_t(steps_), e, kRefloatSalt);
    if (random.uniform() < p) {
      bank_held_[size_t(bin)] = std::max(0.0, bank_held_[size_t(bin)] - emulsion_volume(e));
      el.state[e] = ElementState::floating;
      el.bank_segment[e] = -1;
      el.stranded_since[e] = -1;
    }
  }
  for (size_t e = 0; e < size_t(n); ++e)
    if (el.state[e] != ElementState::floating) el.age[e] += dt;
  time_ = t1;
  ++steps_;
}

Budget FarFieldModel::budget() const {
  Budget b;
  const Elements& el = elements_;
  for (size_t e = 0; e < el.size(); ++e) {
    b.released += el.released_mass[e];
    b.evaporated += el.evaporated_mass[e];
    b.dispersed += el.dispersed_mass[e];
    const double m = el.oil_mass(e);
    switch (el.state[e]) {
      case ElementState::floating:
        b.floating += m;
        break;
      case ElementState::stranded:
        b.stranded += m;
        break;
      case ElementState::left_reach:
        b.left_reach += m;
        break;
      case ElementState::sunk:
        b.sunk += m;
        break;
    }
  }
  return b;
}

}  // namespace farfield
