// `spill-sim bench --compare`: every run is reported, the ratio is the first solver's median wall
// time over the second's, and a bad solver fails before anything runs.

#include "sph/app/solver_comparison.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>

#include "sph/core/config.h"

namespace sph {
namespace {

const std::string kScene =
    std::string(SPILL_SOURCE_DIR) + "/configs/scenes/two_phase_collision.json";

double median_of(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[(v.size() - 1) / 2];
}

TEST(SolverComparison, RatioIsOfTheMedianRuns) {
  SolverComparison c;
  c.scene_file = kScene;
  c.overrides = {"/end_time=0.06", "/output/frame_dt=0.02"};
  c.solvers = {"mtdf", "dfsph"};
  c.repeat = 3;
  const nlohmann::json out = compare_solvers(c, nullptr);
  const auto mtdf = out.at("wall_s").at("mtdf").get<std::vector<double>>();
  const auto dfsph = out.at("wall_s").at("dfsph").get<std::vector<double>>();
  ASSERT_EQ(mtdf.size(), 3u);
  ASSERT_EQ(dfsph.size(), 3u);
  EXPECT_DOUBLE_EQ(out.at("median_wall_s").at("mtdf").get<double>(), median_of(mtdf));
  EXPECT_DOUBLE_EQ(out.at("ratio").get<double>(), median_of(mtdf) / median_of(dfsph));
  // The median runs are reported in full, in the solvers' order.
  ASSERT_EQ(out.at("results").size(), 2u);
  EXPECT_EQ(out.at("results")[0].at("solver"), "mtdf");
  EXPECT_EQ(out.at("results")[1].at("solver"), "dfsph");
  // Only MTDF-SPH has a mixture model and surface tension.
  EXPECT_GT(out.at("mixture_model_s").at("mtdf").get<double>(), 0);
  EXPECT_EQ(out.at("mixture_model_s").at("dfsph").get<double>(), 0);
  EXPECT_GT(out.at("surface_tension_s").at("mtdf").get<double>(), 0);
  EXPECT_EQ(out.at("surface_tension_s").at("dfsph").get<double>(), 0);
}

TEST(SolverComparison, BadRequestsFailBeforeRunning) {
  SolverComparison c;
  c.scene_file = kScene;
  c.solvers = {"mtdf", "no_such_solver"};
  try {
    compare_solvers(c, nullptr);
    FAIL() << "expected an error for an unknown solver";
  } catch (const common::InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("--compare: unknown solver \"no_such_solver\""), std::string::npos) << m;
    EXPECT_NE(m.find("dfsph"), std::string::npos) << m;  // the registered ones are listed
  }
  c.solvers = {"mtdf"};
  EXPECT_THROW(compare_solvers(c, nullptr), common::InputError);
  c.solvers = {"mtdf", "dfsph"};
  c.repeat = 0;
  EXPECT_THROW(compare_solvers(c, nullptr), common::InputError);
}

}  // namespace
}  // namespace sph
