// River inflow and outflow: the inflow layer spans the channel's cross-section, it releases
// speed x cross-section per second, retired water comes back only after its cooldown, oil never
// comes back, and an exhausted reserve is a clear error.

#include "sph/river/river_flow.h"
#include "sph/core/simulation_error.h"

#include <gtest/gtest.h>

#include <string>

#include "sph/core/config.h"
#include "sph/river/river_generator.h"

namespace sph {
namespace {

constexpr Real kSpacing = Real(0.05);
constexpr double kFrameDt = 0.05;

RiverGeneratorConfig straight_river() {
  RiverGeneratorConfig c;
  c.length = 2;
  c.width = 1;
  c.depth = Real(0.3);
  c.bank_slope = 1;
  c.bed_roughness = 0;
  c.bend_amplitude = 0;
  c.narrowing = 1;
  c.widening = 1;
  c.cell_size = Real(0.025);
  return c;
}

FlowConfig flow_config() {
  FlowConfig f;
  f.inflow_x = Real(0.025);
  f.outflow_x = Real(1.5);
  f.speed = Real(1.5);
  f.reserve_s = Real(0.2);
  return f;
}

PhaseMix water() {
  return mix_phases(0, 1000, Real(0.001), 940, Real(0.004));
}

TEST(RiverFlow, InflowLayerSpansTheCrossSection) {
  const RiverGeneratorConfig c = straight_river();
  const Terrain t = generate_river(c);
  const RiverFlow flow(flow_config(), t, 0, kSpacing, Real(1.25e-4), water(), kFrameDt);
  // A trapezoid: 1 m wide at the surface, 0.4 m at the bed, 0.3 m deep.
  const double area = 0.3 * (1.0 + 0.4) / 2;
  const double layer_area = double(flow.layer().size()) * double(kSpacing * kSpacing);
  EXPECT_NEAR(layer_area / area, 1, 0.15) << flow.layer().size() << " particles per layer";
  for (const Vec3& p : flow.layer()) {
    EXPECT_GE(p.z() - kSpacing / 2, t.height_at(p.x(), p.y()) - 1e-5);
    EXPECT_LE(p.z(), 1e-5);
  }
  EXPECT_NEAR(double(flow.inflow_rate()),
              1.5 * double(flow.layer().size()) * 1.25e-4 / double(kSpacing), 1e-6);
}

TEST(RiverFlow, ReleasesLayersRetiresAndRecyclesWater) {
  const Terrain t = generate_river(straight_river());
  FlowConfig config = flow_config();
  config.reserve_s = Real(0.1);  // three layers
  RiverFlow flow(config, t, 0, kSpacing, Real(1.25e-4), water(), kFrameDt);
  FluidParticles fluid;
  flow.allocate(fluid);
  const Index layer = Index(flow.layer().size());
  const Index reserve = fluid.size();
  EXPECT_EQ(reserve % layer, 0u);
  const double interval = double(kSpacing) / 1.5;
  flow.emit(fluid, 3.5 * interval);  // layers 1, 2, 3 are due
  EXPECT_EQ(flow.emitted(), long(3 * layer));
  EXPECT_EQ(fluid.active_count(), 3 * layer);
  for (Index i = 0; i < fluid.active_count(); ++i) EXPECT_FLOAT_EQ(fluid.velocity[i].x(), 1.5f);

  // Two particles pass the outflow plane, one of them oil: both retire, only the water returns.
  fluid.position[0].x() = 1.6f;
  fluid.position[1].x() = 1.7f;
  fluid.oil_fraction[1] = 1;
  const Index water_id = fluid.id[0], oil_id = fluid.id[1];
  const double t_retire = 3.5 * interval;
  flow.after_step(fluid, t_retire, 0);
  EXPECT_EQ(flow.retired(), 2);
  EXPECT_EQ(fluid.active_count(), 3 * layer - 2);
  for (Index i = 0; i < fluid.active_count(); ++i) {
    EXPECT_NE(fluid.id[i], water_id);
    EXPECT_NE(fluid.id[i], oil_id);
  }
  // Emitting the rest of the reserve: the water particle is back only after its cooldown of two
  // frames, and the oil one never; then the reserve runs dry with a clear error.
  const long reserve_layers = long(reserve / layer);
  const double t_dry = double(reserve_layers + 1) * interval;
  ASSERT_LT(t_dry, t_retire + 2 * kFrameDt) << "the test needs the reserve to run out first";
  try {
    flow.emit(fluid, t_dry + 1e-9);
    FAIL() << "expected the reserve to run out";
  } catch (const SimulationError& e) {
    EXPECT_NE(std::string(e.what()).find("reserve_s"), std::string::npos) << e.what();
  }
  for (Index i = 0; i < fluid.active_count(); ++i) EXPECT_NE(fluid.id[i], water_id);
}

TEST(RiverFlow, RecycledWaterReentersAfterItsCooldown) {
  const Terrain t = generate_river(straight_river());
  FlowConfig config = flow_config();
  config.reserve_s = Real(0.07);  // two layers
  RiverFlow flow(config, t, 0, kSpacing, Real(1.25e-4), water(), kFrameDt);
  FluidParticles fluid;
  flow.allocate(fluid);
  const Index layer = Index(flow.layer().size());
  const double interval = double(kSpacing) / 1.5;
  flow.emit(fluid, 2 * interval);
  ASSERT_EQ(fluid.active_count(), 2 * layer);  // the whole reserve is out
  // Every particle leaves at once, at t = 2 intervals; the next layer is due at 3 intervals but
  // the particles are free only 2 frames after leaving.
  for (Index i = 0; i < fluid.active_count(); ++i) fluid.position[i].x() = 1.6f;
  flow.after_step(fluid, 2 * interval, 0);
  EXPECT_EQ(fluid.active_count(), 0u);
  EXPECT_THROW(flow.emit(fluid, 3 * interval), SimulationError);
}

// With `plug`, the inflow buffer's water moves along x as a plug: whatever the solver did to a
// particle there within the step (friction at the bed slowed it), after the step it has moved
// along x by the inflow speed times the step, keeps the solver's motion across and up (the bed
// and banks push it), and moves at the inflow velocity; water past the buffer keeps the solver's
// motion. Without `plug` the buffer's positions are the solver's.
TEST(RiverFlow, TheInflowBufferMovesAsAPlug) {
  const Terrain t = generate_river(straight_river());
  FlowConfig config = flow_config();
  config.buffer = Real(0.2);
  const double interval = double(kSpacing) / 1.5;
  const Real dt = Real(1e-3);
  const Vec3 start0(Real(0.1), 0, Real(-0.2)), start1(Real(0.5), 0, Real(-0.2));
  const Vec3 solver_velocity(Real(0.3), Real(0.1), Real(0.4));
  const Vec3 held(Real(1.5), 0, 0);
  for (bool plug : {true, false}) {
    config.plug = plug;
    RiverFlow flow(config, t, 0, kSpacing, Real(1.25e-4), water(), kFrameDt);
    FluidParticles fluid;
    flow.allocate(fluid);
    flow.emit(fluid, 1.5 * interval);
    ASSERT_GE(fluid.active_count(), 2u);
    // As the solver left them: particle 0 inside the buffer slowed and lifted, 1 past it.
    fluid.position[0] = start0 + solver_velocity * dt;
    fluid.velocity[0] = solver_velocity;
    fluid.position[1] = start1 + solver_velocity * dt;
    fluid.velocity[1] = solver_velocity;
    flow.after_step(fluid, 1.5 * interval, dt);
    const Vec3 moved =
        plug ? Vec3(held.x(), solver_velocity.y(), solver_velocity.z()) * dt : solver_velocity * dt;
    EXPECT_LT((fluid.position[0] - (start0 + moved)).norm(), 1e-6) << "plug " << plug;
    EXPECT_LT((fluid.velocity[0] - held).norm(), 1e-6) << "plug " << plug;
    EXPECT_LT((fluid.position[1] - (start1 + solver_velocity * dt)).norm(), 1e-6);
    EXPECT_LT((fluid.velocity[1] - solver_velocity).norm(), 1e-6);
  }
}

// A forecast whose reach returns too little water goes on with less inflow: a layer the pool
// cannot fill is skipped whole and counted (a solver run stops instead, as above).
TEST(RiverFlow, AForecastSkipsTheLayersAnEmptyPoolCannotFill) {
  const Terrain t = generate_river(straight_river());
  FlowConfig config = flow_config();
  config.reserve_s = Real(0.07);  // two layers
  RiverFlow flow(config, t, 0, kSpacing, Real(1.25e-4), water(), kFrameDt);
  FluidParticles fluid;
  flow.allocate(fluid);
  const Index layer = Index(flow.layer().size());
  const double interval = double(kSpacing) / double(config.speed);
  flow.emit(fluid, 5.5 * interval, /*skip_when_empty=*/true);  // 5 layers due, 2 in the pool
  EXPECT_EQ(fluid.active_count(), 2 * layer);
  EXPECT_EQ(flow.skipped_layers(), 3);
  EXPECT_EQ(flow.emitted(), long(2 * layer));
  // The schedule goes on: the next layer is due at 6 intervals, and is skipped too.
  flow.emit(fluid, 6.5 * interval, true);
  EXPECT_EQ(flow.skipped_layers(), 4);
  EXPECT_THROW(flow.emit(fluid, 7.5 * interval), SimulationError);
}

}  // namespace
}  // namespace sph
