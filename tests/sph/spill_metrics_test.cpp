// Spill metrics on hand-placed oil: area from occupied top-view cells, the leading edge, bank
// contact on the side the oil touches, arrival at a watch point, and the oil volume.

#include "sph/river/spill_metrics.h"

#include <gtest/gtest.h>

#include <cmath>

#include "sph/river/river_generator.h"

namespace sph {
namespace {

TEST(SpillMetrics, MeasuresHandPlacedOil) {
  RiverGeneratorConfig c;  // straight reach for x < 2 m: water edges at y = +-1 m
  c.bed_roughness = 0;
  const Terrain t = generate_river(c);
  const Real d = Real(0.05);
  WatchPointConfig intake;
  intake.name = "intake";
  intake.x = Real(1.5);
  intake.y = Real(0.9);
  intake.radius = Real(0.1);
  SpillMetrics metrics(t, 0, Real(0.5), d, {intake});

  FluidParticles f;
  const PhaseMix oil = mix_phases(1, 1000, Real(0.001), 940, Real(0.004));
  const PhaseMix water = mix_phases(0, 1000, Real(0.001), 940, Real(0.004));
  const Real volume = Real(1.25e-4);
  f.add(Vec3(Real(1.0), Real(0.0), 0), Vec3::Zero(), volume, water);  // not oil
  const SpillFrame& before = metrics.measure(f, 0.0, 0.0);
  EXPECT_EQ(before.slick_area_m2, 0);
  EXPECT_EQ(before.front_distance_m, 0);

  // Two oil particles in one cell, one in another; one 1.2 m downstream of the leak by the
  // left bank's water line (within a diameter of the edge at y = 1 m).
  f.add(Vec3(Real(0.61), Real(0.01), 0), Vec3::Zero(), volume, oil);
  f.add(Vec3(Real(0.62), Real(0.02), 0), Vec3::Zero(), volume, oil);
  f.add(Vec3(Real(1.51), Real(0.97), 0), Vec3::Zero(), volume, oil);
  const SpillFrame& now = metrics.measure(f, 2.0, 3.0 * double(volume));
  EXPECT_NEAR(now.slick_area_m2, 2 * double(d * d), 1e-9);
  EXPECT_NEAR(now.front_distance_m, 1.01, 1e-5);
  EXPECT_NEAR(now.left_bank_m, double(d), 1e-9);  // one bin of bank
  EXPECT_EQ(now.right_bank_m, 0);
  EXPECT_NEAR(now.oil_in_reach_m3, 3 * double(volume), 1e-9);
  ASSERT_TRUE(metrics.arrival("intake"));
  EXPECT_EQ(*metrics.arrival("intake"), 2.0);

  // Bank contact is cumulative: the oil leaves the bank, the oiled length stays.
  f.position[3].y() = 0;
  EXPECT_NEAR(metrics.measure(f, 3.0, 0).left_bank_m, double(d), 1e-9);
  const nlohmann::json j = metrics.to_json();
  EXPECT_EQ(j.at("first_left_bank_contact_s"), 2.0);
  EXPECT_TRUE(j.at("first_right_bank_contact_s").is_null());
  EXPECT_EQ(j.at("frames").size(), 3u);
}

}  // namespace
}  // namespace sph

namespace sph {
namespace {

// Two hand-placed slicks: a 3 x 3 block of oil particles one diameter apart (9 cells), a lone
// particle three cells away (a second patch; one cell away diagonally would join the first), a
// particle stacked on the block (no new cell, more volume) and water (ignored).
TEST(SlickShape, AreaRadiusThicknessAndPatchesOfHandPlacedOil) {
  const Real d = Real(0.1), volume = Real(0.001);
  const PhaseMix oil = mix_phases(1, 1000, Real(0.001), 940, Real(0.004));
  const PhaseMix water = mix_phases(0, 1000, Real(0.001), 940, Real(0.004));
  FluidParticles f;
  for (int x = 0; x < 3; ++x)
    for (int y = 0; y < 3; ++y)
      f.add(Vec3(0.05f + d * x, 0.05f + d * y, 0), Vec3::Zero(), volume, oil);
  f.add(Vec3(0.05f, 0.05f, 0.1f), Vec3::Zero(), volume, oil);
  f.add(Vec3(0.65f, 0.05f, 0), Vec3::Zero(), volume, oil);
  f.add(Vec3(1.05f, 1.05f, 0), Vec3::Zero(), volume, water);
  const SlickShape s = measure_slick(f, d);
  EXPECT_NEAR(s.area_m2, 10 * 0.01, 1e-7);  // float cells
  EXPECT_NEAR(s.equivalent_radius_m, std::sqrt(0.1 / M_PI), 1e-6);
  EXPECT_NEAR(s.oil_volume_m3, 11 * 0.001, 1e-7);
  EXPECT_NEAR(s.mean_thickness_m, 0.011 / 0.1, 1e-6);
  EXPECT_EQ(s.patches, 2);
  EXPECT_NEAR(s.largest_patch_share, 10.0 / 11.0, 1e-6);    // the block and its stacked particle
  f.add(Vec3(0.35f, 0.35f, 0), Vec3::Zero(), volume, oil);  // touches the block at a corner
  f.add(Vec3(0.45f, 0.25f, 0), Vec3::Zero(), volume, oil);
  f.add(Vec3(0.55f, 0.15f, 0), Vec3::Zero(), volume, oil);  // and on to the lone particle
  EXPECT_EQ(measure_slick(f, d).patches, 1);
  EXPECT_NEAR(measure_slick(f, d).largest_patch_share, 1.0, 1e-6);
  EXPECT_EQ(measure_slick(FluidParticles(), d).largest_patch_share, 0);
}

}  // namespace
}  // namespace sph
