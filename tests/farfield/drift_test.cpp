// The drift's local laws, computed here from their textbook forms with the C library's cube
// root, against farfield::local_drift over the depths a river has (1 mm to 100 m).
#include <gtest/gtest.h>

#include <cmath>

#include "farfield/model/drift.h"

namespace {

// Manning's friction as a drag coefficient: Cf/2 = g n^2 / h^(1/3).
double half_friction(double n, double h) {
  return 9.81 * n * n / std::cbrt(h);
}

TEST(LocalDrift, TheLogLawAndElderFischerMixingHoldFromMillimetresToAHundredMetres) {
  const farfield::DriftSettings settings;
  for (const double n : {0.02, 0.035, 0.06}) {
    for (double h = 1e-3; h <= 100; h *= 1.37) {
      farfield::FlowSample s;
      s.where = farfield::FlowWhere::water;
      s.depth = h;
      s.u = 1.2;
      s.v = -0.5;
      s.manning = n;
      const farfield::LocalDrift d = farfield::local_drift(s, settings);
      const double cf = half_friction(n, h);
      const double factor = 1 + std::sqrt(cf) / 0.41;
      const double shear = 1.3 * std::sqrt(cf);  // |u| = 1.3 m/s
      EXPECT_NEAR(d.u / (factor * s.u), 1, 1e-13) << "n " << n << " h " << h;
      EXPECT_NEAR(d.v / (factor * s.v), 1, 1e-13) << "n " << n << " h " << h;
      EXPECT_NEAR(d.d_along / (5.93 * h * shear), 1, 1e-13) << "n " << n << " h " << h;
      EXPECT_NEAR(d.d_across / (0.6 * h * shear), 1, 1e-13) << "n " << n << " h " << h;
    }
  }
}

}  // namespace
