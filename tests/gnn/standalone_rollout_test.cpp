// Rollouts without the recording's help (gnn/eval/scene_rollout.h): from a recorded frame of a
// simulated river, the scene's own leak, inflow and outflow act on the model's frames.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>

#include "gnn/data/frame_window.h"
#include "gnn/eval/metrics.h"
#include "gnn/eval/scene_rollout.h"
#include "gnn/eval/solver_rollout.h"
#include "gnn/models/model_registry.h"
#include "infer/ensemble_scores.h"
#include "infer/map_views.h"
#include "infer/trajectory_scores.h"
#include "sph/app/scene_runner.h"
#include "sph/river/river_flow.h"
#include "sph/scene/scene_loader.h"
#include "tests/gnn/run_folder.h"

namespace fs = std::filesystem;

namespace {

const std::string kRiverSmall = std::string(SPILL_SOURCE_DIR) + "/configs/scenes/river_small.json";
// A short leak inside one simulated second of river_small (20 frames of 0.05 s), with a watch
// point 0.6 m downstream of the leak that its oil reaches.
const std::vector<std::string> kShortLeak = {
    "/leaks/0/start=0.1", "/leaks/0/duration=0.5", "/end_time=1.0",
    R"(/watch_points=[{"name": "intake", "x": 1.6, "y": 0, "radius": 0.2}])"};

class Standalone : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("spill_standalone_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    sph::RunOptions run;
    run.out_dir = dir_ / "run";
    scene_ = sph::load_scene(kRiverSmall, kShortLeak);
    sph::run_scene(scene_, run);
    recording_ = run_folder::read(dir_ / "run", dir_ / "view");
    // The constant-velocity floor: its next position is known without the model's code.
    const gnn::DatasetMetadata& m = recording_.metadata;
    simulator_ = std::make_unique<gnn::LearnedSimulator>(
        gnn::make_model({{"model", "constant_velocity"}, {"radius", m.connectivity_radius}},
                        "test"),
        gnn::Normalisation::from_metadata(m, 0.0, 0.0), m.bounds, m.particle_radius);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // The recording's frames from .. from + frames as a rollout that predicted them exactly.
  gnn::RolloutResult recorded_rollout(int64_t from, int64_t frames) const {
    const gnn::Trajectory& t = recording_.trajectory;
    const auto span = [&](const torch::Tensor& x) {
      return x.slice(0, from, from + frames + 1).clone();
    };
    return {from, span(t.position), span(t.active), span(t.oil_fraction),
            std::vector<double>(size_t(frames), 0.0)};
  }
  // `r` with every particle that is oil at a frame moved `shift` m downstream there.
  static gnn::RolloutResult oil_moved(const gnn::RolloutResult& r, float shift) {
    gnn::RolloutResult moved = r;
    moved.position = r.position.clone();
    const auto oil = r.oil_fraction >= gnn::kOilFractionThreshold;
    moved.position.select(2, 0).add_(oil.to(torch::kFloat32) * shift);
    return moved;
  }

  fs::path dir_;
  sph::LoadedScene scene_;
  run_folder::Read recording_;
  std::unique_ptr<gnn::LearnedSimulator> simulator_;
};

}  // namespace

TEST_F(Standalone, SourcesAndSinksComeFromTheSceneNotTheRecording) {
  const gnn::Trajectory& t = recording_.trajectory;
  const double dt = recording_.metadata.frame_dt;
  const int64_t from = 2, frames = t.frames() - 1 - from;
  const gnn::RolloutResult r = gnn::standalone_rollout(*simulator_, t, from, frames, dt);
  ASSERT_EQ(r.position.size(0), frames + 1);

  // It starts from the recorded frame.
  EXPECT_TRUE(torch::equal(r.active[0], t.active[from]));
  EXPECT_TRUE(
      torch::equal(r.position[0].index({r.active[0]}), t.position[from].index({t.active[from]})));

  // One frame on, a particle away from the river's buffers keeps its recorded velocity (the
  // floor's rule, computed here from the recording).
  const sph::FlowConfig& flow = *scene_.config.flow;
  const auto x0 = t.position[from], before = t.position[from - 1];
  const auto steady = t.active[from] & t.active[from - 1] & r.active[1] &
                      (x0.select(1, 0) > flow.inflow_x + flow.buffer + 0.1) &
                      (x0.select(1, 0) < flow.outflow_x - flow.buffer - 0.1);
  ASSERT_GT(steady.sum().item<int64_t>(), 500);
  const auto expected = (2 * x0 - before).index({steady});
  EXPECT_LT((r.position[1].index({steady}) - expected).abs().max().item<float>(), 1e-5);
  // Water in the inflow buffer is held at the inflow speed.
  const auto held = t.active[from] & r.active[1] & (x0.select(1, 0) < flow.inflow_x + 0.05);
  ASSERT_GT(held.sum().item<int64_t>(), 10);
  const auto held_velocity = (r.position[1] - x0).index({held}) / dt;
  EXPECT_LT((held_velocity.select(1, 0) - flow.speed).abs().max().item<float>(), 1e-3);

  // The leak's oil leaves the outlet on the recorded schedule (the same emitter code): a layer
  // shows in the same frame, or one frame later in the solver's run when it fell due during that
  // frame's last solver step (the solver releases at its steps, a forecast at its frames).
  const auto oil = t.particle_type == gnn::kOil;
  ASSERT_GT(oil.sum().item<int64_t>(), 10);
  const auto first_active = [&](const torch::Tensor& active) {
    // Frame of first activity per particle (frames + 1 when never active).
    const auto frame = torch::arange(active.size(0)).unsqueeze(1).expand(active.sizes());
    return torch::where(active, frame, torch::full_like(frame, active.size(0))).amin(0);
  };
  const auto predicted_start = first_active(r.active).index({oil});
  const auto recorded_start = first_active(t.active.slice(0, from)).index({oil});
  const auto lag = recorded_start - predicted_start;
  EXPECT_TRUE(((lag == 0) | (lag == 1)).all().item<bool>()) << lag;
  EXPECT_GT((lag == 0).sum().item<int64_t>(), oil.sum().item<int64_t>() / 2);
  // The inflow releases its layers on the scene's schedule: as many particles enter as in the
  // solver's run, to one layer (the restored frame may sit either side of a layer's due time).
  const auto entered = [&](const torch::Tensor& active) {
    return (active.slice(0, 1) & ~active.slice(0, 0, -1))
        .index({torch::indexing::Slice(), ~oil})
        .sum()
        .item<int64_t>();
  };
  const int64_t layer = int64_t(sph::RiverFlow::inflow_layer(flow, *scene_.config.terrain_grid,
                                                             scene_.config.terrain->water_level,
                                                             scene_.config.particle_diameter())
                                    .size());
  EXPECT_NEAR(double(entered(r.active)), double(entered(t.active.slice(0, from))), double(layer));
  EXPECT_GT(entered(r.active), 5 * layer);
  // Nothing active past the outflow plane: it retired there.
  for (int64_t k = 1; k <= frames; ++k)
    EXPECT_FALSE((r.active[k] & (r.position[k].select(1, 0) > flow.outflow_x)).any().item<bool>())
        << "frame " << k;
}

// The scores compare a particle only while it is the same parcel on both sides.
TEST(ActiveSince, MarksTheFrameEachRunOfActiveFramesBegan) {
  // Particle 0: always active; 1: enters at frame 2; 2: leaves at 1, re-enters at 3.
  const auto active =
      torch::tensor({1, 0, 1, 1, 0, 0, 1, 1, 0, 1, 1, 1}, torch::kBool).view({4, 3});
  const auto expected = torch::tensor({0, -1, 0, 0, -1, -1, 0, 2, -1, 0, 2, 3}).view({4, 3});
  EXPECT_TRUE(torch::equal(infer::active_since(active), expected)) << infer::active_since(active);
}

// A dataset without a scene cannot be rolled out standalone: the error names the option that
// replays the recording instead.
// The ceiling (gnn/eval/solver_rollout.h): the scene's own solver from a recorded frame, jittered
// by 1e-3 of a diameter, stays far closer to the recording than the constant-velocity floor
// (measured on the standard dataset: 1.3 % of the floor's error 5 frames on), keeps the
// recording's particle count within 2 %, and moves: a jitter changes its frames.
TEST_F(Standalone, TheJitteredSolverFollowsTheRecordingFarCloserThanTheFloor) {
  const gnn::Trajectory& t = recording_.trajectory;
  const double dt = recording_.metadata.frame_dt;
  const double diameter = 2 * recording_.metadata.particle_radius;
  const int64_t from = 2, frames = 5;
  const auto ceiling = gnn::solver_rollout(t, from, frames, dt, 1e-3 * diameter, 1);
  const auto other = gnn::solver_rollout(t, from, frames, dt, 1e-3 * diameter, 2);
  const auto floor = gnn::standalone_rollout(*simulator_, t, from, frames, dt);
  ASSERT_EQ(ceiling.position.size(0), frames + 1);
  EXPECT_TRUE(torch::equal(ceiling.position[0], t.position[from]));
  const auto truth = t.position[from + frames];
  const auto truth_active = t.active[from + frames];
  const auto both = ceiling.active[frames] & floor.active[frames] & truth_active;
  const double ceiling_mse = gnn::position_mse(ceiling.position[frames], truth, both);
  const double floor_mse = gnn::position_mse(floor.position[frames], truth, both);
  EXPECT_GT(ceiling_mse, 0);
  EXPECT_LT(ceiling_mse, 0.1 * floor_mse);
  const double active = double(truth_active.sum().item<int64_t>());
  EXPECT_NEAR(double(ceiling.active[frames].sum().item<int64_t>()), active, 0.02 * active);
  EXPECT_FALSE(torch::equal(ceiling.position[1], other.position[1]));
  EXPECT_THROW(gnn::solver_rollout(t, from, frames, dt, -1, 1), std::invalid_argument);
}

TEST_F(Standalone, ATrajectoryWithoutASceneNamesTheReplayOption) {
  gnn::Trajectory t = recording_.trajectory;
  t.scene = nlohmann::json::object();
  try {
    gnn::standalone_rollout(*simulator_, t, 2, 3, recording_.metadata.frame_dt);
    FAIL() << "rolled out without a scene";
  } catch (const gnn::DatasetError& e) {
    EXPECT_NE(std::string(e.what()).find("--replay-recorded-sources"), std::string::npos)
        << e.what();
  }
}

// The responder's errors frame by frame: nil for the recording scored against itself; the oil
// moved 0.2 m downstream gives a leading-edge error of 0.2 m wherever the front is inside the
// reach, and an earlier arrival at the watch point, by at most the time the flow takes for 0.2 m
// plus a frame.
TEST_F(Standalone, ResponderErrorsAreNilForTheRecordingAndSeeTheOilMoved) {
  const gnn::Trajectory& t = recording_.trajectory;
  const gnn::DatasetMetadata& m = recording_.metadata;
  const int64_t from = 2, frames = t.frames() - 1 - from;
  gnn::SpillScene scene(t);
  ASSERT_EQ(scene.watch_point_names(), std::vector<std::string>{"intake"});
  const auto recorded = infer::recorded_measures(&scene, t, from, frames);
  ASSERT_TRUE(recorded.arrival.at("intake")) << "the test's oil must reach the watch point";
  gnn::RolloutResult same = recorded_rollout(from, frames);
  const auto nil = infer::score_frames(same, t, m, &scene, recorded, from, frames);
  ASSERT_EQ(nil.slick_area_error.size(), size_t(frames));
  int defined = 0;
  for (int64_t k = 0; k < frames; ++k) {
    EXPECT_EQ(nil.front_error[k], 0.0) << k;
    if (std::isfinite(nil.slick_area_error[k])) {
      EXPECT_EQ(nil.slick_area_error[k], 0.0) << k;
      ++defined;
    }
  }
  EXPECT_GT(defined, frames / 2);
  EXPECT_EQ(infer::watch_arrival_time_error(nil), 0.0);

  const double shift = 0.2;
  gnn::RolloutResult moved = oil_moved(same, float(shift));
  const auto scores = infer::score_frames(moved, t, m, &scene, recorded, from, frames);
  const double reach_end = scene_.config.flow->outflow_x - 1.0;  // leak at x = 1
  int inside = 0;
  for (int64_t k = 0; k < frames; ++k)
    if (recorded.front[k] > 0 && recorded.front[k] + shift < reach_end) {
      EXPECT_NEAR(scores.front_error[k], shift, 1e-4) << k;
      ++inside;
    }
  EXPECT_GT(inside, 5);
  const auto early = scores.predicted.arrival.at("intake");
  ASSERT_TRUE(early);
  const double lead = *recorded.arrival.at("intake") - *early;
  EXPECT_GE(lead, 0.0);
  EXPECT_LE(lead, shift / 1.0 + m.frame_dt);  // the oil moves at about 1.5 m/s, never under 1
  EXPECT_DOUBLE_EQ(*infer::watch_arrival_time_error(scores), lead);
}

// The scores a chaotic flow allows, on the same two rollouts: the recording against itself has
// divergence 0 and a perfect footprint; oil moved 0.2 m downstream costs exactly 0.2^2 = 0.04 m^2
// of oil-cloud Sinkhorn divergence (a shifted cloud's cost, whatever the epsilon), and its
// footprint scores better the wider the window.
TEST_F(Standalone, ForecastScoresAreNilForTheRecordingAndSeeTheOilMoved) {
  const gnn::Trajectory& t = recording_.trajectory;
  const gnn::DatasetMetadata& m = recording_.metadata;
  const int64_t from = 2, frames = t.frames() - 1 - from;
  gnn::SpillScene scene(t);
  const auto recorded = infer::recorded_measures(&scene, t, from, frames);
  gnn::RolloutResult same = recorded_rollout(from, frames);
  const auto nil = infer::score_frames(same, t, m, &scene, recorded, from, frames);
  // The leak (0.1 s to 0.6 s) ends 0.6 s - t(from) after the start.
  ASSERT_TRUE(nil.leak_end);
  EXPECT_NEAR(*nil.leak_end, 0.6 - t.time[from].item<double>(), 1e-6);
  const auto costly = infer::costly_frames(frames, m.frame_dt, nil.leak_end);
  ASSERT_EQ(costly.back(), frames);
  int taken = 0;
  for (int64_t k : costly) {
    ASSERT_TRUE(std::isfinite(nil.sinkhorn_fluid[size_t(k - 1)])) << k;
    EXPECT_NEAR(nil.sinkhorn_fluid[size_t(k - 1)], 0.0, 1e-9) << k;
    EXPECT_NEAR(nil.sinkhorn_oil[size_t(k - 1)], 0.0, 1e-9) << k;
    ++taken;
  }
  EXPECT_GE(taken, 2);
  for (const auto& scale : nil.fss)
    for (double v : scale)
      if (std::isfinite(v)) {
        EXPECT_DOUBLE_EQ(v, 1.0);
      }

  gnn::RolloutResult moved = oil_moved(same, 0.2f);
  const auto scores = infer::score_frames(moved, t, m, &scene, recorded, from, frames);
  int with_oil = 0;
  for (int64_t k : costly) {
    if (recorded.slick_area[size_t(k - 1)] <= 0) continue;
    EXPECT_NEAR(scores.sinkhorn_oil[size_t(k - 1)], 0.04, 2e-4) << k;  // float positions
    const size_t f = size_t(k - 1);
    EXPECT_LT(scores.fss[0][f], scores.fss[3][f]) << k;
    EXPECT_LT(scores.fss[0][f], 1.0) << k;
    ++with_oil;
  }
  EXPECT_GE(with_oil, 1);
}

// An ensemble of three members, one the recording and two with its oil 0.2 m downstream: where
// the leading edge is inside the reach, the fair CRPS of {f, f + 0.2, f + 0.2} against f is
// 0.4/3 - 0.8/12 = 0.2/3 m; while only the moved members have reached the watch point, the fair
// Brier score of p = 2/3 against "not yet" is 4/9 - (2/9)/2 = 1/3, and 0 before and after.
TEST_F(Standalone, AnEnsembleIsScoredByFairCrpsAndBrier) {
  const gnn::Trajectory& t = recording_.trajectory;
  const gnn::DatasetMetadata& m = recording_.metadata;
  const int64_t from = 2, frames = t.frames() - 1 - from;
  gnn::SpillScene scene(t);
  const auto recorded = infer::recorded_measures(&scene, t, from, frames);
  gnn::RolloutResult same = recorded_rollout(from, frames);
  gnn::RolloutResult moved = oil_moved(same, 0.2f);
  const auto truth = infer::score_frames(same, t, m, &scene, recorded, from, frames);
  const auto ahead = infer::score_frames(moved, t, m, &scene, recorded, from, frames);
  const infer::EnsembleScores e = infer::score_ensemble({truth, ahead, ahead}, m.frame_dt);
  const double reach_end = scene_.config.flow->outflow_x - 1.0;
  int inside = 0;
  for (int64_t k = 0; k < frames; ++k)
    if (recorded.front[size_t(k)] > 0 && recorded.front[size_t(k)] + 0.2 < reach_end) {
      EXPECT_NEAR(e.crps_front[size_t(k)], 0.2 / 3, 1e-4) << k;
      EXPECT_NEAR(e.front_spread[size_t(k)], std::sqrt(0.04 / 3), 1e-4) << k;
      ++inside;
    }
  EXPECT_GT(inside, 5);
  const double arrived = *recorded.arrival.at("intake"),
               early = *ahead.predicted.arrival.at("intake");
  ASSERT_LT(early, arrived);
  int between = 0;
  for (int64_t k = 0; k < frames; ++k) {
    const double now = double(k + 1) * m.frame_dt;
    const double expected = now >= early - 1e-9 && now < arrived - 1e-9 ? 1.0 / 3 : 0.0;
    EXPECT_NEAR(e.brier_watch[size_t(k)], expected, 1e-12) << k;
    between += expected > 0 ? 1 : 0;
  }
  EXPECT_GE(between, 1);
  // Every member the recording: a sure and right forecast.
  const infer::EnsembleScores exact = infer::score_ensemble({truth, truth}, m.frame_dt);
  for (double v : exact.crps_front)
    if (std::isfinite(v)) {
      EXPECT_EQ(v, 0.0);
    }
  EXPECT_EQ(exact.crps_watch_arrival, 0.0);
}

// The probability-of-oiling picture shades each cell by the share of members with oil there: two
// members that are both the recording draw the oil at full strength (near-black), one recording
// beside one without oil draws it at half (never that dark), and no oil draws none.
TEST_F(Standalone, TheOilingPictureShadesCellsByTheShareOfMembersWithOil) {
  const gnn::Trajectory& t = recording_.trajectory;
  const gnn::DatasetMetadata& m = recording_.metadata;
  const int64_t from = 2, frames = t.frames() - 1 - from;
  gnn::RolloutResult same = recorded_rollout(from, frames);
  gnn::RolloutResult clean = same;
  clean.oil_fraction = torch::zeros_like(same.oil_fraction);
  const infer::MapViewRenderer renderer(t, m);
  const auto dark_pixels = [](const common::RgbImage& image) {
    int dark = 0;
    for (size_t p = 0; p + 2 < image.pixels.size(); p += 3)
      dark += image.pixels[p] < 80 && image.pixels[p + 1] < 80 && image.pixels[p + 2] < 80;
    return dark;
  };
  const double cell = 2 * m.particle_radius;
  EXPECT_GT(dark_pixels(renderer.render_oiling({same, same}, frames, cell)), 20);
  EXPECT_EQ(dark_pixels(renderer.render_oiling({same, clean}, frames, cell)), 0);
  EXPECT_EQ(dark_pixels(renderer.render_oiling({clean, clean}, frames, cell)), 0);
  const auto half = renderer.render_oiling({same, clean}, frames, cell).pixels;
  EXPECT_NE(half, renderer.render_oiling({clean, clean}, frames, cell).pixels);
}

// A jittered member (gnn::standalone_rollout's jitter): the floor's first frame moves each
// particle by its own offset, no more than the jitter (its velocity is unchanged), and the same
// seed gives the same member.
TEST_F(Standalone, AJitteredMemberMovesByItsOffsetAndRepeatsWithItsSeed) {
  const gnn::Trajectory& t = recording_.trajectory;
  const double dt = recording_.metadata.frame_dt;
  const double jitter = 1e-3 * 2 * recording_.metadata.particle_radius;
  const auto plain = gnn::standalone_rollout(*simulator_, t, 2, 1, dt);
  const auto member = gnn::standalone_rollout(*simulator_, t, 2, 1, dt, {}, {}, jitter, 5);
  const auto again = gnn::standalone_rollout(*simulator_, t, 2, 1, dt, {}, {}, jitter, 5);
  const auto both = plain.active[1] & member.active[1] & t.active[2];
  const auto moved = (member.position[1] - plain.position[1]).index({both}).abs();
  EXPECT_GT(moved.max().item<double>(), 0.1 * jitter);
  // Positions are float32: a difference of two positions a few metres out carries a few 1e-7 m.
  EXPECT_LE(moved.max().item<double>(), jitter + 2e-6);
  EXPECT_TRUE(torch::equal(member.position[1], again.position[1]));
}

// An event seen by one side only counts the time from that sighting to the rollout's end; seen
// by neither, it does not count.
TEST(ResponderErrors, AnArrivalSeenByOneSideCountsToTheEnd) {
  infer::TrajectoryScores s;
  s.rollout_seconds = 4.0;
  s.recorded.arrival = {{"a", 1.0}, {"b", 1.5}, {"c", std::nullopt}};
  s.predicted.arrival = {{"a", 1.25}, {"b", std::nullopt}, {"c", std::nullopt}};
  EXPECT_DOUBLE_EQ(*infer::watch_arrival_time_error(s), (0.25 + 2.5) / 2);
  s.recorded.arrival = {{"c", std::nullopt}};
  EXPECT_FALSE(infer::watch_arrival_time_error(s));
}
