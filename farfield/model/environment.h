#pragma once
// The weather and the water over the forecast: water temperature, the 10 m wind (speed and the
// direction it blows from), the wave height (given, or raised by the wind over the river's
// fetch) and ice cover. Series are piecewise linear in time.

#include <optional>

#include "farfield/model/drift.h"
#include "farfield/model/weathering.h"
#include "reach/hydrograph.h"

namespace farfield {

struct Environment {
  reach::Hydrograph water_temperature_c{15.0};
  reach::Hydrograph wind_speed{0.0};
  reach::Hydrograph wind_from_deg{0.0};
  std::optional<reach::Hydrograph> wave_height;
  double fetch = 500;  // m: how far the wind blows over water (waves when not given)
  bool ice = false;
  double water_density = 1000;    // kg/m^3
  bool river_dispersion = false;  // the river's turbulence disperses oil too (weathering.h)
  bool sinking = false;           // oil as dense as the water sinks to the bed

  WeatherNow weather_at(double t) const;
  // The wind's velocity (where it blows to); zero under ice, which shelters the oil.
  Wind wind_at(double t) const;
};

}  // namespace farfield
