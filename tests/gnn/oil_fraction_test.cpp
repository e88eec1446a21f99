// Oil is a fraction, not a label (issue 14, item 0): MTDF-SPH moves oil between particles, so
// the learned simulators read each particle's oil fraction, predict its change with an update that
// keeps the oil volume, and are scored on the footprint spill.json reports.
#include <gtest/gtest.h>

#include <iostream>
#include <nlohmann/json.hpp>

#include "gnn/data/frame_window.h"
#include "gnn/eval/metrics.h"
#include "gnn/eval/rollout.h"
#include "gnn/eval/spill_measures.h"
#include "gnn/models/learned_simulator.h"
#include "sph/io/tensor_recorder.h"
#include "sph/river/slick_shape.h"
#include "sph/scene/scene_loader.h"
#include "sph/simulation/simulation.h"

namespace {

// Oil poured into water at rest with MTDF-SPH, whose drift exchanges oil between the particles
// where the phases meet: 400 water particles, the jet adds oil for 0.2 s; 2 s in 20 frames.
const char* kPourScene = R"({
  "name": "pour", "solver": "mtdf", "particle_radius": 0.02, "end_time": 2.0,
  "output": {"frame_dt": 0.1},
  "materials": {"water": {"density": 1000, "viscosity": 0.001},
                "oil": {"density": 940, "viscosity": 0.004}},
  "boxes": [{"min": [0, 0, 0], "max": [0.4, 0.4, 0.6]}],
  "fluid_blocks": [{"min": [0, 0, 0], "max": [0.4, 0.4, 0.16], "material": "water"}],
  "emitters": [{"centre": [0.2, 0.2, 0.35], "radius": 0.05, "rate": 0.002, "speed": 1.5,
                "direction": [0, 0, -1], "stop": 0.2, "material": "oil"}]})";

struct RecordedPour {
  gnn::Trajectory trajectory;
  std::vector<sph::SlickShape> live;  // measure_slick on the simulator's own state per frame
  double rest_volume = 0;
};

RecordedPour record_pour() {
  const nlohmann::json scene = nlohmann::json::parse(kPourScene);
  const sph::LoadedScene s = sph::parse_scene(scene, "pour.json");
  sph::Simulation sim(s.config);
  sph::TensorRecorder recorder(sim, 1);
  RecordedPour out;
  const sph::Real cell = s.config.particle_diameter();
  recorder.record(sim);
  out.live.push_back(sph::measure_slick(sim.fluid(), cell));
  for (int frame = 1; frame <= 20; ++frame) {
    sim.advance_to(0.1 * frame, frame);
    recorder.record(sim);
    out.live.push_back(sph::measure_slick(sim.fluid(), cell));
  }
  out.rest_volume = double(sim.fluid().rest_volume[0]);
  out.trajectory = gnn::from_recorded(recorder.take(), scene["materials"]);
  out.trajectory.scene = s.resolved;
  return out;
}

// Every ordered pair of distinct particles among `members` (a fully connected neighbourhood).
torch::Tensor all_pairs(const std::vector<int64_t>& members) {
  std::vector<int64_t> senders, receivers;
  for (int64_t a : members)
    for (int64_t b : members)
      if (a != b) {
        senders.push_back(a);
        receivers.push_back(b);
      }
  return torch::stack({torch::tensor(senders), torch::tensor(receivers)});
}

TEST(OilFraction, TheLocalUpdateKeepsTheOilVolumeAndTheRange) {
  torch::manual_seed(3);
  const int64_t n = 500;
  auto fraction = torch::rand({n});
  fraction.slice(0, 0, 100).fill_(0);
  fraction.slice(0, 100, 200).fill_(1);
  // Large and biased: taken as it is, it would add 100 particles' worth of oil and clip hundreds.
  const auto change = torch::randn({n}) * 0.5 + 0.2;
  // Neighbourhoods: particle i with the next 12 (a ring), both directions.
  std::vector<int64_t> senders, receivers;
  for (int64_t i = 0; i < n; ++i)
    for (int64_t k = 1; k <= 12; ++k) {
      senders.push_back(i);
      receivers.push_back((i + k) % n);
      senders.push_back((i + k) % n);
      receivers.push_back(i);
    }
  const auto pairs = torch::stack({torch::tensor(senders), torch::tensor(receivers)});
  const auto updated = gnn::local_fraction_update(fraction, change, pairs);
  EXPECT_GE(updated.min().item<double>(), 0.0);
  EXPECT_LE(updated.max().item<double>(), 1.0);
  const double before = fraction.to(torch::kFloat64).sum().item<double>();
  // Float32 storage of 500 values in [0, 1]: 1e-6 relative is ~30 roundings.
  EXPECT_NEAR(updated.to(torch::kFloat64).sum().item<double>(), before, 1e-6 * before);
  const auto moved = updated - fraction;
  EXPECT_GT(moved.abs().max().item<double>(), 0.3);  // it did move oil
  // No particle moved against its prediction, nor further than asked.
  EXPECT_TRUE((moved * change >= -1e-7).all().item<bool>());
  EXPECT_TRUE((moved.abs() <= change.abs() + 1e-6).all().item<bool>());
}

TEST(OilFraction, OilMovesOnlyBetweenNeighbours) {
  // Two neighbourhoods that do not touch: 0-3 holds oil and exchanges it; 4-7 is clean water that
  // a biased model asks to gain oil everywhere.
  const auto fraction = torch::tensor({1.0f, 0.8f, 0.1f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f});
  const auto change = torch::tensor({-0.2f, -0.1f, 0.2f, 0.1f, 0.05f, 0.05f, 0.05f, 0.05f});
  const auto pairs = torch::cat({all_pairs({0, 1, 2, 3}), all_pairs({4, 5, 6, 7})}, 1);
  const auto updated = gnn::local_fraction_update(fraction, change, pairs);
  // Within the oily neighbourhood the change balances (0.3 offered, 0.3 asked): applied as it is.
  EXPECT_TRUE(torch::allclose(updated.slice(0, 0, 4), (fraction + change).slice(0, 0, 4)));
  // The water far from any oil stays clean.
  EXPECT_TRUE(torch::equal(updated.slice(0, 4), torch::zeros({4})));
  // With no pairs at all, nothing moves.
  EXPECT_TRUE(torch::equal(
      gnn::local_fraction_update(fraction, change, torch::zeros({2, 0}, torch::kInt64)), fraction));
  // An unbalanced neighbourhood moves what both sides allow: 0.3 offered, 0.6 asked.
  const auto greedy = torch::tensor({-0.2f, -0.1f, 0.4f, 0.2f, 0.0f, 0.0f, 0.0f, 0.0f});
  const auto shared = gnn::local_fraction_update(fraction, greedy, all_pairs({0, 1, 2, 3}));
  EXPECT_NEAR(shared.slice(0, 2, 4).sum().item<double>(), 0.1 + 0.3, 1e-6);
  EXPECT_NEAR(shared.sum().item<double>(), fraction.sum().item<double>(), 1e-6);
}

TEST(OilFraction, TheFractionChannelIsConservedInARollout) {
  const RecordedPour pour = record_pour();
  const gnn::Trajectory& t = pour.trajectory;
  gnn::DatasetMetadata m;
  m.frame_dt = 0.1;
  m.bounds = {{{0, 0.4}, {0, 0.4}, {0, 0.6}}};
  m.vel_mean = torch::zeros({3});
  m.acc_mean = torch::zeros({3});
  m.vel_std = torch::full({3}, 0.01f);
  m.acc_std = torch::full({3}, 0.001f);
  torch::manual_seed(11);
  auto model =
      gnn::make_model({{"model", "gns"}, {"latent", 16}, {"layers", 2}, {"radius", 0.08}}, "test");
  // An untrained model (outputs ~0.05) with a wide fraction scale proposes large, biased changes:
  // the hard case for conservation (clipping at 0 and 1 on many particles).
  gnn::LearnedSimulator simulator(model, gnn::Normalisation::from_metadata(m, 0, 20.0), m.bounds);
  const int64_t from = 5, frames = 8;
  const auto r = gnn::rollout(simulator, t, from, frames, m.frame_dt);
  double largest_change = 0;
  for (int64_t k = 1; k <= frames; ++k) {
    const auto kept = r.active[k - 1] & r.active[k];
    const auto launched = r.active[k] & ~r.active[k - 1];
    ASSERT_TRUE(torch::equal(kept, r.active[k - 1])) << "no particle leaves this scene";
    // The oil of the particles present before, plus what the leak brought in at its recorded
    // fraction.
    const double before = r.oil_fraction[k - 1].index({r.active[k - 1]}).sum().item<double>();
    const double brought = t.oil_fraction[from + k].index({launched}).sum().item<double>();
    const double after = r.oil_fraction[k].index({r.active[k]}).sum().item<double>();
    EXPECT_NEAR(after, before + brought, 1e-5 * (before + brought)) << "frame " << k;
    largest_change = std::max(
        largest_change,
        (r.oil_fraction[k] - r.oil_fraction[k - 1]).index({kept}).abs().max().item<double>());
  }
  EXPECT_GT(largest_change, 0.05) << "the model moved no oil: nothing was tested";
  const auto all_active = r.oil_fraction.index({r.active});
  EXPECT_GE(all_active.min().item<double>(), 0.0);
  EXPECT_LE(all_active.max().item<double>(), 1.0);
}

TEST(OilFraction, TheScoredFootprintIsSpillJsons) {
  const RecordedPour pour = record_pour();
  const gnn::Trajectory& t = pour.trajectory;
  const gnn::SpillScene scene(t);
  EXPECT_DOUBLE_EQ(scene.particle_volume(), pour.rest_volume);
  int64_t relabelled = 0;  // oil by fraction but water by type, or the reverse, over all frames
  for (int64_t k = 0; k < t.frames(); ++k) {
    const auto fraction = t.oil_fraction[k];
    const sph::SlickShape scored = sph::measure_slick(
        gnn::fluid_of_frame(t.position[k], t.active[k], fraction, scene.particle_volume()),
        sph::Real(scene.cell()));
    const sph::SlickShape& live = pour.live[size_t(k)];
    EXPECT_EQ(scored.area_m2, live.area_m2) << "frame " << k;
    EXPECT_EQ(scored.patches, live.patches) << "frame " << k;
    EXPECT_NEAR(scored.oil_volume_m3, live.oil_volume_m3, 1e-6 * live.oil_volume_m3 + 1e-12)
        << "frame " << k;
    // The IoU of eval and compare uses the same cells and the same rule.
    const auto oil = t.active[k] & (fraction >= gnn::kOilFractionThreshold);
    const auto xy = t.position[k].index({oil}).slice(1, 0, 2);
    const auto by_type = t.active[k] & (t.particle_type == gnn::kOil);
    relabelled += (oil != by_type).logical_and(t.active[k]).sum().item<int64_t>();
    EXPECT_DOUBLE_EQ(gnn::top_view_iou(xy, xy, scene.cell()), 1.0);
    const double cells = live.area_m2 / (scene.cell() * scene.cell());
    const auto distinct_cells =
        std::get<0>(torch::unique_dim(torch::floor(xy.to(torch::kFloat64) / scene.cell()), 0));
    EXPECT_NEAR(double(distinct_cells.size(0)), cells, 1e-6);
  }
  // Measured 12: without them the test could not tell the fraction's rule from the type's.
  EXPECT_GT(relabelled, 0) << "no particle changed phase: the scene tests nothing";
  std::cout << relabelled << " particle-frames are oil by fraction but not by type, or the "
            << "reverse\n";
}

}  // namespace
