// Fay's gravity-inertia fit on synthetic slicks whose areas follow a known law: the slope and k1
// come back, and the window opens and closes where the slick says.

#include "sph/river/fay_spreading.h"

#include "sph/river/spill_metrics.h"

#include <gtest/gtest.h>

#include <cmath>

namespace sph {
namespace {

const double kPi = std::acos(-1.0);

// A slick of volume `volume` released at area a0 whose area grows as a0 + c t^p, sampled every
// 0.05 s to `end`; its thickness is volume / area.
std::vector<std::pair<double, SlickShape>> synthetic(double a0, double c, double p, double volume,
                                                     double end) {
  std::vector<std::pair<double, SlickShape>> frames;
  for (int k = 0; k * 0.05 <= end + 1e-9; ++k) {
    const double t = k * 0.05;
    SlickShape s;
    s.area_m2 = a0 + c * std::pow(t, p);
    s.oil_volume_m3 = volume;
    s.mean_thickness_m = volume / s.area_m2;
    frames.emplace_back(t, s);
  }
  return frames;
}

TEST(FaySpreading, RecoversSlopeAndK1OfASlickSpreadingAsFaySays) {
  const double delta = 0.06, g = 9.81, volume = 0.032, a0 = 0.16, d = 0.01;
  // Fay's rate with k1 = 0.9: pi k1^2 (Delta g V)^(1/2) m^2 per second.
  const double c = kPi * 0.81 * std::sqrt(delta * g * volume);
  const FayFit fit = fit_fay_gravity_inertia(synthetic(a0, c, 1, volume, 2), delta, g, d);
  ASSERT_TRUE(fit.valid);
  EXPECT_NEAR(fit.slope, 1, 1e-9);
  EXPECT_NEAR(fit.k1, 0.9, 1e-9);
  // The window opens once the slick has grown by a fifth of a0 (0.032 m^2 at c = 0.35 m^2/s:
  // t = 0.091 s, so the frame at 0.1 s) and runs to the end, the slick staying thicker than 2 d.
  EXPECT_NEAR(fit.window_start_s, 0.1, 1e-9);
  EXPECT_NEAR(fit.window_end_s, 2, 1e-9);
  EXPECT_EQ(fit.frames, 39);
}

TEST(FaySpreading, TheWindowClosesWhereTheSlickThinsToTwoDiameters) {
  const double delta = 0.06, g = 9.81, volume = 0.032, a0 = 0.16, d = 0.04;
  // Area 0.16 + 0.5 t^1.3: the slope comes back whatever the rate, and the slick reaches two
  // diameters (area 0.4 m^2) at t = (0.24 / 0.5)^(1 / 1.3) = 0.569 s, so 0.55 s is the last frame.
  const FayFit fit = fit_fay_gravity_inertia(synthetic(a0, 0.5, 1.3, volume, 2), delta, g, d);
  ASSERT_TRUE(fit.valid);
  EXPECT_NEAR(fit.slope, 1.3, 1e-9);
  EXPECT_NEAR(fit.window_end_s, 0.55, 1e-9);
  // A slick that never grows, or is thin from the start, gives no fit.
  EXPECT_FALSE(fit_fay_gravity_inertia(synthetic(a0, 0, 1, volume, 2), delta, g, d).valid);
  EXPECT_FALSE(fit_fay_gravity_inertia(synthetic(a0, 0.5, 1, 0.001, 2), delta, g, d).valid);
  EXPECT_FALSE(fit_fay_gravity_inertia({}, delta, g, d).valid);
}

// spill.json of a still-water run carries the fit of its own frames: 24 oil particles of a
// diameter's cube each, stacked over 3, 4, 6, 8, 10 and 16 top-view cells in frames 0.05 s
// apart (mean thickness 8, 6, 4, 3, 2.4 and 1.5 diameters), so the window is 0.05-0.2 s.
TEST(FaySpreading, StillWaterSpillJsonCarriesTheFitOfItsFrames) {
  const Real d = Real(0.04);
  const PhaseMix oil = mix_phases(1, 1000, Real(0.001), 940, Real(0.004));
  StillWaterSlickMetrics metrics(d, 0.06, 9.81);
  const int cells[] = {3, 4, 6, 8, 10, 16};
  for (int k = 0; k < 6; ++k) {
    FluidParticles f;
    for (int i = 0; i < 24; ++i)
      f.add(Vec3(d * (Real(i % cells[k]) + Real(0.5)), Real(0.5) * d, d * Real(i / cells[k])),
            Vec3::Zero(), d * d * d, oil);
    metrics.measure(f, 0.05 * k);
  }
  const nlohmann::json j = metrics.to_json();
  const nlohmann::json& fit = j.at("fay_gravity_inertia");
  const FayFit expected = fit_fay_gravity_inertia(metrics.frames(), 0.06, 9.81, double(d));
  ASSERT_TRUE(expected.valid);
  EXPECT_NEAR(fit.at("window_s")[0].get<double>(), 0.05, 1e-9);
  EXPECT_NEAR(fit.at("window_s")[1].get<double>(), 0.2, 1e-9);
  EXPECT_EQ(fit.at("frames"), 4);
  EXPECT_DOUBLE_EQ(fit.at("slope").get<double>(), expected.slope);
  EXPECT_DOUBLE_EQ(fit.at("k1").get<double>(), expected.k1);
  EXPECT_TRUE(j.at("definitions").contains("fay_gravity_inertia"));

  StillWaterSlickMetrics still(d, 0.06, 9.81);  // a slick that never spreads: no fit
  FluidParticles f;
  f.add(Vec3::Zero(), Vec3::Zero(), d * d * d, oil);
  still.measure(f, 0), still.measure(f, 0.05), still.measure(f, 0.1);
  EXPECT_TRUE(still.to_json().at("fay_gravity_inertia").is_null());
}

}  // namespace
}  // namespace sph
