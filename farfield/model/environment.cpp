#include "farfield/model/environment.h"

#include <cmath>

namespace farfield {

WeatherNow Environment::weather_at(double t) const {
  WeatherNow w;
  w.water_temperature_c = water_temperature_c.at(t);
  w.wind_speed = ice ? 0.0 : wind_speed.at(t);
  w.ice = ice;
  w.water_density = water_density;
  if (ice)
    w.wave_height = 0;
  else if (wave_height)
    w.wave_height = wave_height->at(t);
  else
    w.wave_height = wave_height_from_wind(w.wind_speed, fetch);
  return w;
}

Wind Environment::wind_at(double t) const {
  Wind w;
  if (ice) return w;
  const double speed = wind_speed.at(t);
  const double to = (wind_from_deg.at(t) + 180) * 3.14159265358979323846 / 180;
  w.east = speed * std::sin(to);
  w.north = speed * std::cos(to);
  return w;
}

}  // namespace farfield
