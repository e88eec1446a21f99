// The pushforward schedule (train/pushforward.h): which unroll counts a batch may draw at a
// training step and how often, and the configs that cannot be followed.
#include <gtest/gtest.h>

#include <array>
#include <filesystem>

#include "common/config_error.h"
#include "train/pushforward.h"
#include "train/training_config.h"

namespace {

train::TrainingConfig lagrangebench_like() {
  train::TrainingConfig c;
  c.pushforward_schedule = {{0, 0, 18}, {100, 1, 2}, {200, 2, 1}, {300, 3, 1}};
  return c;
}

// The share of `draws` batches at `step` that unrolled 0..3 frames.
std::array<double, 4> shares(const train::TrainingConfig& c, int64_t step, int draws) {
  std::mt19937_64 sampler(7);
  std::array<double, 4> counts{};
  for (int k = 0; k < draws; ++k)
    counts.at(size_t(train::pushforward_frames(c, step, sampler))) += 1;
  for (auto& n : counts) n /= draws;
  return counts;
}

}  // namespace

// Only the stages open at a step are drawn, each with its weight's share of the open weights.
// 40,000 draws: a share's standard error is at most 0.0025, the tolerance 0.01 is four of them.
TEST(PushforwardSchedule, DrawsTheOpenStagesInProportionToTheirWeights) {
  const auto c = lagrangebench_like();
  const int draws = 40000;
  EXPECT_EQ(shares(c, 0, draws), (std::array<double, 4>{1, 0, 0, 0}));
  EXPECT_EQ(shares(c, 99, draws), (std::array<double, 4>{1, 0, 0, 0}));
  const auto second = shares(c, 100, draws);
  EXPECT_NEAR(second[0], 0.9, 0.01);
  EXPECT_NEAR(second[1], 0.1, 0.01);
  EXPECT_EQ(second[2] + second[3], 0.0);
  const auto all = shares(c, 5000, draws);
  const std::array<double, 4> expected{18.0 / 22, 2.0 / 22, 1.0 / 22, 1.0 / 22};
  for (size_t k = 0; k < 4; ++k) EXPECT_NEAR(all[k], expected[k], 0.01) << k << " frames";
  EXPECT_EQ(train::most_pushforward_frames(c), 3);
}

// A fixed count is the count at every step, and draws nothing: runs without a schedule keep the
// random streams their windows and noise were drawn from before schedules existed.
TEST(PushforwardSchedule, AFixedCountDrawsNothing) {
  train::TrainingConfig c;
  c.pushforward_steps = 2;
  std::mt19937_64 sampler(3), untouched(3);
  for (int64_t step : {0, 10, 100000}) EXPECT_EQ(train::pushforward_frames(c, step, sampler), 2);
  EXPECT_EQ(sampler, untouched);
  EXPECT_EQ(train::most_pushforward_frames(c), 2);
}

TEST(PushforwardSchedule, AScheduleThatCannotBeFollowedIsAnErrorNamingTheKey) {
  const std::string file =
      (std::filesystem::path(SPILL_SOURCE_DIR) / "configs/training/gns_smoke.json").string();
  auto pointer_of = [&](const std::vector<std::string>& overrides) -> std::string {
    try {
      train::load_training_config(file, overrides);
    } catch (const common::ConfigError& e) {
      EXPECT_EQ(e.file(), file);
      return e.pointer();
    }
    return "accepted";
  };
  const std::string stages =
      R"(/pushforward_schedule=[{"from_step":0,"unrolls":0,"weight":18},)"
      R"({"from_step":400,"unrolls":1,"weight":2},{"from_step":1200,"unrolls":2,"weight":1}])";
  EXPECT_EQ(pointer_of({stages}), "accepted");
  EXPECT_EQ(pointer_of({R"(/pushforward_schedule=[{"from_step":5,"unrolls":1}])"}),
            "/pushforward_schedule/0/from_step");
  EXPECT_EQ(pointer_of({R"(/pushforward_schedule=[{"from_step":0},{"from_step":9,"unrolls":1},)"
                        R"({"from_step":3,"unrolls":2}])"}),
            "/pushforward_schedule/2/from_step");
  EXPECT_EQ(pointer_of({stages, "/pushforward_steps=1"}), "/pushforward_steps");
  EXPECT_EQ(pointer_of({R"(/pushforward_schedule=[{"from_step":0,"unrolls":4}])"}),
            "/pushforward_schedule/0/unrolls");
  EXPECT_EQ(pointer_of({R"(/pushforward_schedule=[{"from_step":0,"weight":0}])"}),
            "/pushforward_schedule/0/weight");
  EXPECT_EQ(pointer_of({R"(/pushforward_schedule=[{"from_step":0,"unroll":1}])"}),
            "/pushforward_schedule/0/unroll");
}
