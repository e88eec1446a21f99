#include "farfield/model/spreading.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace farfield {

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kGravity = 9.81;
constexpr double kWaterViscosity = 1e-6;  // m^2/s
constexpr double kInertial = 1.53, kGravityViscous = 1.21, kViscous = 1.45;
}  // namespace

double FaySlick::area_at(double age) const {
  if (age <= onset) return initial_area;
  return std::sqrt(initial_area * initial_area + rate * rate * (age - onset));
}

FaySlick fay_slick(double volume, double oil_density, double water_density) {
  const double buoyancy = (water_density - oil_density) / water_density;
  if (!(buoyancy > 0))
    throw std::invalid_argument("the oil (" + std::to_string(oil_density) +
                                " kg/m^3) is not lighter than the water (" +
                                std::to_string(water_density) + " kg/m^3): it would sink");
  FaySlick s;
  const double g = kGravity * buoyancy;
  s.initial_area = kPi * std::pow(kGravityViscous, 4) / (kInertial * kInertial) *
                   std::pow(std::pow(volume, 5) * g / (kWaterViscosity * kWaterViscosity), 1.0 / 6);
  s.onset = std::pow(kGravityViscous / kInertial, 4) * std::cbrt(volume / (kWaterViscosity * g));
  s.rate = kPi * kViscous * kViscous * std::cbrt(volume * volume * g / std::sqrt(kWaterViscosity));
  return s;
}

}  // namespace farfield
