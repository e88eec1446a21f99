#pragma once
// The far field's Lagrangian elements: each is a parcel of oil on the water's surface, carried
// as structure-of-arrays so that a step over 1e5 of them streams through memory. An element's
// oil is split into the oil record's pseudo-components (distillation cuts), each losing mass to
// evaporation on its own; what an element loses is kept on it (evaporated, dispersed), so that
// the budget sums what every element holds and closes to rounding.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace farfield {

// sunk: denser than the water it floated on, it went to the bed where it was
// (/environment/sinking).
enum class ElementState : std::uint8_t { floating = 0, stranded = 1, left_reach = 2, sunk = 3 };

struct Elements {
  int cuts = 0;                         // pseudo-components per element
  std::vector<double> x, y;             // map coordinates (m)
  std::vector<double> mass;             // [e * cuts + c] oil mass of cut c still on element e (kg)
  std::vector<double> released_mass;    // kg of oil the element started with
  std::vector<double> evaporated_mass;  // kg it has lost to the air
  std::vector<double> dispersed_mass;   // kg it has lost into the water column as droplets
  std::vector<double> water_fraction;   // of the emulsion's volume (0 to the oil's maximum)
  std::vector<double> droplet_area;     // m^2 of water droplets per m^3 of oil (ADIOS-2's S)
  std::vector<double> emulsion_start;   // age (s) at which water uptake began, or -1
  std::vector<double> area;             // m^2 of water surface the element covers
  std::vector<int> slick;               // the Fay slick it was born in (a release's step)
  std::vector<double> slick_share;      // its share of that slick's oil (0-1]
  std::vector<double> spread_radius;    // m: how far its slick's spreading has moved it out
  std::vector<double> age;              // s since release
  std::vector<double> stranded_since;   // s of forecast time when it stranded (or -1)
  std::vector<int> bank_segment;        // the bank bin holding it when stranded, else -1
  std::vector<ElementState> state;

  size_t size() const { return x.size(); }
  double oil_mass(size_t e) const {
    double m = 0;
    for (int c = 0; c < cuts; ++c) m += mass[e * size_t(cuts) + size_t(c)];
    return m;
  }
  // Appends one element; returns its index.
  size_t add(double x_m, double y_m, const std::vector<double>& cut_masses, double area_m2,
             int slick_index, double share, double age_s) {
    x.push_back(x_m);
    y.push_back(y_m);
    double total = 0;
    for (double m : cut_masses) {
      mass.push_back(m);
      total += m;
    }
    released_mass.push_back(total);
    evaporated_mass.push_back(0);
    dispersed_mass.push_back(0);
    water_fraction.push_back(0);
    droplet_area.push_back(0);
    emulsion_start.push_back(-1);
    area.push_back(area_m2);
    slick.push_back(slick_index);
    slick_share.push_back(share);
    spread_radius.push_back(0);
    age.push_back(age_s);
    stranded_since.push_back(-1);
    bank_segment.push_back(-1);
    state.push_back(ElementState::floating);
    return x.size() - 1;
  }
};

}  // namespace farfield
