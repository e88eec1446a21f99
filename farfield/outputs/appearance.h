#pragma once
// How a slick looks from the air at a thickness: the Bonn Agreement Oil Appearance Code
// (Bonn Agreement Aerial Operations Handbook, 2016), by which responders read and report slicks.
// A film thicker than a class's range is the next class; 5 has no upper bound.

#include <array>

#include "common/bitmap_font.h"

namespace farfield {

struct AppearanceClass {
  int code = 0;
  const char* appearance = "";
  double from_um = 0, to_um = 0;  // film thickness, micrometres
  common::Rgb colour;             // on the forecast's maps
};

inline const std::array<AppearanceClass, 5>& bonn_classes() {
  static const std::array<AppearanceClass, 5> classes = {{
      {1, "sheen (silvery/grey)", 0.04, 0.3, {175, 175, 185}},
      {2, "rainbow", 0.3, 5.0, {150, 95, 185}},
      {3, "metallic", 5.0, 50.0, {95, 100, 120}},
      {4, "discontinuous true oil colour", 50.0, 200.0, {125, 75, 25}},
      {5, "continuous true oil colour", 200.0, 1e12, {45, 22, 5}},
  }};
  return classes;
}

// The class of a film `thickness_m` thick (below 0.04 um: class 1, the thinnest seen).
inline const AppearanceClass& bonn_class(double thickness_m) {
  const double um = thickness_m * 1e6;
  for (const AppearanceClass& c : bonn_classes())
    if (um < c.to_um) return c;
  return bonn_classes().back();
}

}  // namespace farfield
