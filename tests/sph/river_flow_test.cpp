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

// Water is water by the one oil rule: a particle that leaves with a trace of oil (a fraction under
// one half, which the mixture model or a learned update gave it) returns to the pool and re-enters
// as the river's pure water, and the oil it carried counts as oil that left the reach, as does
// an oil particle's, which never returns.
TEST(RiverFlow, WaterWithATraceOfOilReturnsCleanAndItsOilIsCounted) {
  const Terrain t = generate_river(straight_river());
  FlowConfig config = flow_config();
  config.reserve_s = Real(0.07);  // two layers
  const Real volume = Real(1.25e-4);
  RiverFlow flow(config, t, 0, kSpacing, volume, water(), kFrameDt);
  FluidParticles fluid;
  flow.allocate(fluid);
  const Index layer = Index(flow.layer().size());
  const double interval = double(kSpacing) / double(config.speed);
  flow.emit(fluid, 2 * interval);
  ASSERT_EQ(fluid.active_count(), 2 * layer);  // the whole reserve is out
  const PhaseMix trace = mix_phases(Real(0.3), 1000, Real(0.001), 940, Real(0.004));
  const PhaseMix oil = mix_phases(Real(0.5), 1000, Real(0.001), 940, Real(0.004));
  // Every particle leaves: one with a trace, one oil (at the threshold), the rest clean water.
  for (Index i = 0; i < fluid.active_count(); ++i) fluid.position[i].x() = 1.6f;
  // The last slots: they retire first, so the trace is at the head of the pool.
  const Index last = fluid.active_count() - 1;
  fluid.set_mix(last, trace);
  fluid.set_mix(last - 1, oil);
  const Index trace_id = fluid.id[last], oil_id = fluid.id[last - 1];
  const double t_leave = 2 * interval;
  flow.after_step(fluid, t_leave, 0);
  ASSERT_EQ(fluid.active_count(), 0u);
  // Fractions and volumes are stored in single precision: 1e-6 relative.
  EXPECT_NEAR(flow.oil_left_volume(), (0.3 + 0.5) * double(volume), 1e-6 * double(volume));
  // After the cooldown every layer but the oil particle's returns, the trace's clean.
  const double t_back = t_leave + 2 * kFrameDt + 1e-9;
  flow.emit(fluid, t_back, /*skip_when_empty=*/true);
  bool trace_back = false;
  for (Index i = 0; i < fluid.active_count(); ++i) {
    EXPECT_NE(fluid.id[i], oil_id);
    EXPECT_EQ(fluid.oil_fraction[i], 0) << "particle " << fluid.id[i];
    EXPECT_EQ(fluid.rest_density[i], water().rest_density);
    EXPECT_EQ(fluid.viscosity[i], water().viscosity);
    EXPECT_EQ(fluid.type[i], ParticleType::kWater);
    trace_back = trace_back || fluid.id[i] == trace_id;
  }
  EXPECT_TRUE(trace_back) << "the water with a trace of oil did not return";
  // One layer short of the reserve (the oil particle's place is empty), so one more layer skipped.
  EXPECT_EQ(fluid.active_count(), layer);
  // A saved state keeps the count.
  RiverFlow restored(config, t, 0, kSpacing, volume, water(), kFrameDt);
  restored.restore(flow.state());
  EXPECT_EQ(restored.oil_left_volume(), flow.oil_left_volume());
}

// A frame computed outside the solver (a learned one, 0.2 s) moved particles from `previous` to
// their predicted positions; the buffers' hold is applied as the solver's steps apply it: water
// that entered the outflow buffer during the frame moved at its predicted pace until it got there
// and at the inflow speed after, water in the buffer all frame at the inflow speed, water that
// ends the frame in the inflow buffer at the inflow velocity; elsewhere the prediction stands.
TEST(RiverFlow, AnOutsideFrameHoldsTheBuffersForTheTimeSpentInThem) {
  const Terrain t = generate_river(straight_river());
  FlowConfig config = flow_config();
  config.buffer = Real(0.1);  // the outflow buffer starts at 1.4 m, the inflow's ends at 0.125 m
  RiverFlow flow(config, t, 0, kSpacing, Real(1.25e-4), water(), kFrameDt);
  FluidParticles fluid;
  const std::vector<Vec3> previous = {Vec3(1.2f, 0.1f, -0.1f), Vec3(1.45f, 0, -0.1f),
                                      Vec3(0.8f, 0, -0.1f), Vec3(0.03f, 0, -0.1f)};
  const std::vector<Vec3> predicted = {Vec3(1.6f, 0.12f, -0.12f), Vec3(1.9f, 0.05f, -0.1f),
                                       Vec3(1.0f, 0.02f, -0.1f), Vec3(0.1f, 0.03f, -0.08f)};
  const Real dt = Real(0.2);
  for (size_t i = 0; i < previous.size(); ++i)
    fluid.add(predicted[i], (predicted[i] - previous[i]) / dt, Real(1.25e-4), water());
  flow.hold_buffers_over_frame(fluid, previous, dt);
  // Half the frame to reach the buffer at 2 m/s, then 0.1 s at 1.5 m/s; across and up as
  // predicted.
  EXPECT_NEAR(fluid.position[0].x(), 1.4 + 0.5 * 1.5 * 0.2, 1e-6);
  EXPECT_FLOAT_EQ(fluid.position[0].y(), 0.12f);
  EXPECT_FLOAT_EQ(fluid.position[0].z(), -0.12f);
  EXPECT_FLOAT_EQ(fluid.velocity[0].x(), 1.5f);
  // In the buffer all frame: 0.3 m along x.
  EXPECT_NEAR(fluid.position[1].x(), 1.45 + 1.5 * 0.2, 1e-6);
  EXPECT_FLOAT_EQ(fluid.position[1].y(), 0.05f);
  // Between the buffers: the prediction.
  EXPECT_EQ(fluid.position[2], predicted[2]);
  // In the inflow buffer: the inflow velocity, across and up included.
  EXPECT_NEAR(fluid.position[3].x(), 0.03 + 1.5 * 0.2, 1e-6);
  EXPECT_FLOAT_EQ(fluid.position[3].y(), 0.0f);
  EXPECT_FLOAT_EQ(fluid.position[3].z(), -0.1f);
  EXPECT_EQ(fluid.velocity[3], Vec3(1.5f, 0, 0));
}

// Water thrown over a bank beyond the terrain's side, or upstream past its start, has left the
// reach as water that fell below the lowest ground has: it retires, counts as fallen, and
// comes back to the inflow as water; a particle still over the ground stays.
TEST(RiverFlow, WaterThrownBeyondTheTerrainsEdgeRetiresAsFallen) {
  const Terrain t = generate_river(straight_river());
  RiverFlow flow(flow_config(), t, 0, kSpacing, Real(1.25e-4), water(), kFrameDt);
  FluidParticles fluid;
  flow.allocate(fluid);
  flow.emit(fluid, 3.5 * double(kSpacing) / 1.5);
  const Index active = fluid.active_count();
  ASSERT_GE(active, 4u);
  const Real edge = Real(0.5) * t.cell_size;
  fluid.position[0] = Vec3(Real(0.5), t.max_y() + edge + Real(0.01), Real(0.1));
  fluid.position[1] = Vec3(Real(0.5), t.origin_y - edge - Real(0.01), Real(0.1));
  fluid.position[2] = Vec3(t.origin_x - edge - Real(0.01), 0, Real(0.1));
  fluid.position[3] = Vec3(Real(0.5), t.max_y() + edge - Real(0.01), Real(0.1));  // over ground
  const Index kept = fluid.id[3];
  const size_t pooled = flow.state().at("pool_ids").size();
  flow.after_step(fluid, 0.1, 0);
  EXPECT_EQ(flow.retired(), 3);
  EXPECT_EQ(flow.fallen(), 3);
  EXPECT_EQ(fluid.active_count(), active - 3);
  bool still_there = false;
  for (Index i = 0; i < fluid.active_count(); ++i) still_there |= fluid.id[i] == kept;
  EXPECT_TRUE(still_there);
  EXPECT_EQ(flow.state().at("pool_ids").size(), pooled + 3);  // all three were water
  flow.after_step(fluid, 0.1, 0);
  EXPECT_EQ(flow.state().at("pool_ids").size(), pooled + 3);  // nothing more retires
  EXPECT_EQ(flow.fallen(), 3);
}

}  // namespace
}  // namespace sph
