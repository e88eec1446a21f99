// Emitters: the released volume matches rate x duration, layers leave the outlet with the outflow
// velocity on schedule, identities stay fixed with an `active` mask, and bad emitters are errors.

#include "sph/boundary/emitter.h"

#include <gtest/gtest.h>

#include "sph/core/config.h"
#include "sph/core/lattice.h"
#include "sph/scene/scene_loader.h"
#include "sph/simulation/simulation.h"

namespace sph {
namespace {

EmitterConfig disc_emitter() {
  EmitterConfig e;
  e.shape = "disc";
  e.centre = Vec3(0.2f, 0.2f, 0.3f);
  e.direction = Vec3(0, 0, -2);  // normalised on use
  e.radius = Real(0.02);
  e.speed = Real(1.3);
  e.rate = Real(2e-4);
  e.start = Real(0.1);
  e.stop = Real(2.1);
  return e;
}

TEST(Emitter, ReleasesRateTimesDuration) {
  const Real spacing = Real(0.01);
  const Real volume = lattice_rest_volume(KernelKind::kCubicSpline, 2 * spacing, spacing);
  Emitter emitter(disc_emitter(), spacing, volume, mix_phases(1, 1000, 0.01f, 940, 0.04f));
  FluidParticles fluid;
  emitter.allocate(fluid);
  ASSERT_EQ(fluid.active_count(), 0u);
  ASSERT_EQ(emitter.layer().size(), 13u);  // lattice points within 2 spacings of the centre
  for (const Vec3& p : emitter.layer())
    EXPECT_NEAR(double((p - disc_emitter().centre)[2]), 0, 1e-6);

  const double rate = 2e-4;
  for (double t = 0; t <= 2.5; t += 0.01) {
    emitter.emit(fluid, t);
    const double expected = t < 0.1 ? 0 : rate * (std::min(t, 2.1) - 0.1);
    const double released = double(fluid.active_count()) * double(volume);
    // At any moment within one layer of the nominal rate: half a layer from releasing whole layers
    // at mid-interval, and the layers' cadence of whole layers with a partial last one.
    EXPECT_NEAR(released, expected, double(volume) * 13 + 1e-9) << "t = " << t;
  }
  // In all, rate x duration to half a particle (whole particles, not whole layers).
  const double total = double(fluid.active_count()) * double(volume);
  EXPECT_NEAR(total, rate * 2.0, 0.5 * double(volume) + 1e-12);
  EXPECT_EQ(fluid.active_count(), emitter.capacity());
  // Released particles are oil, move with the outflow velocity, and left the outlet downward.
  for (Index i = 0; i < fluid.active_count(); ++i) {
    EXPECT_EQ(fluid.type[i], ParticleType::kOil);
    EXPECT_NEAR(double(fluid.velocity[i][2]), -1.3, 1e-6);
    EXPECT_LE(fluid.position[i][2], Real(0.3) + Real(1e-6));
  }
}

TEST(Emitter, SimulationKeepsIdentitiesAndActivatesOnSchedule) {
  const nlohmann::json j = nlohmann::json::parse(R"({
    "particle_radius": 0.01, "end_time": 0.3,
    "boxes": [{"min": [0, 0, 0], "max": [0.3, 0.3, 0.4]}],
    "fluid_blocks": [{"min": [0, 0, 0], "max": [0.3, 0.3, 0.04]}],
    "emitters": [{"centre": [0.15, 0.15, 0.3], "radius": 0.03, "speed": 1.0, "rate": 0.001,
                  "start": 0.05, "stop": 0.25, "material": "oil"}]})");
  Simulation sim(parse_scene(j, "emitter.json").config);
  const Index blocks = 15 * 15 * 2;
  const Index total = sim.fluid().size();
  ASSERT_EQ(sim.fluid().active_count(), blocks);
  ASSERT_GT(total, blocks);
  sim.advance_to(0.04, 1);
  EXPECT_EQ(sim.fluid().active_count(), blocks) << "nothing before the start";
  sim.advance_to(0.3, 2);
  EXPECT_EQ(sim.fluid().active_count(), total) << "everything after the stop";
  // Identities stay a permutation of 0..N-1 and the oil came from the emitter.
  std::vector<int> seen(total, 0);
  Index oil = 0;
  for (Index i = 0; i < total; ++i) {
    ++seen[sim.fluid().id[i]];
    oil += sim.fluid().type[i] == ParticleType::kOil;
  }
  for (Index k = 0; k < total; ++k) ASSERT_EQ(seen[k], 1);
  EXPECT_EQ(oil, total - blocks);
  // Whole particles: rate x duration rounded to the nearest particle (8e-6 m^3 here; the outlet's
  // layer holds 9).
  const double particle = double(sim.fluid().rest_volume[0]);
  const double released = double(total - blocks) * particle;
  EXPECT_NEAR(released, 0.001 * 0.2, 0.5 * particle + 1e-12);
}

TEST(Emitter, BadEmittersAreErrors) {
  nlohmann::json j = nlohmann::json::parse(R"({
    "particle_radius": 0.01, "end_time": 0.3,
    "boxes": [{"min": [0, 0, 0], "max": [0.3, 0.3, 0.4]}],
    "emitters": [{"centre": [0.15, 0.15, 0.9], "rate": 0.001, "stop": 0.25}]})");
  try {
    parse_scene(j, "emitter.json");
    FAIL() << "an emitter above the tank must be rejected";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.pointer(), "/emitters/0/centre") << e.what();
  }
  j["emitters"][0]["centre"] = {0.15, 0.15, 0.3};
  j["emitters"][0]["start"] = 0.3;
  EXPECT_THROW(parse_scene(j, "emitter.json"), ConfigError);  // stop before start
  j["emitters"][0]["start"] = 0.0;
  j["emitters"][0]["rate"] = -1;
  EXPECT_THROW(parse_scene(j, "emitter.json"), ConfigError);
}

}  // namespace
}  // namespace sph
