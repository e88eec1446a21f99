// A learned forecast keeps the river's water and closes its oil budget (issue 48, section 1):
// over the whole leak of river_small at 40 solver steps per frame, from the settled river at the
// leak's start, each committed model of the f40 results run standalone by spill-infer predict
// refills the inflow from the water it retires (no layer skipped) and accounts for the oil
// released, on the water plus what left the reach, within one particle's volume at every frame.
// Before, water with a trace of oil never returned and the global fraction update put traces
// everywhere: these three models skipped 182-510 inflow layers over the 8 whole-leak test
// trajectories (docs/results/f40_levers.md).
//
// The active particle count then follows the model's own dynamics: a model that piles water up
// or lets it run out faster than MTDF-SPH holds more or fewer particles in the reach. GNS holds
// the recording's count within 5 % at every frame (3.7 % measured); DPI-Nets and the PAGATNet
// student drain by 8-9 % towards the end of the leak, a model error that `compare` reports as
// active_deviation_max (docs/results/f40_levers.md), not a fault of the bookkeeping tested here.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "gnn/data/dataset.h"
#include "infer/commands.h"
#include "sph/app/scene_runner.h"
#include "sph/scene/scene_loader.h"
#include "tests/gnn/run_folder.h"

namespace fs = std::filesystem;

namespace {

const std::string kSource = SPILL_SOURCE_DIR;
const std::string kRiverSmall = kSource + "/configs/scenes/river_small.json";
// One model of each kind trained on river_small at 0.2 s per frame (docs/results/f40_levers.md);
// the PAGATNet teacher (0.4 s a frame) is left to the committed comparisons, which score it.
struct Model {
  std::string checkpoint;
  bool holds_the_count;  // keeps the recording's active count within 5 % (measured)
};
const std::vector<Model> kModels = {{kSource + "/docs/results/crossover_runs/gns_f40.pt", true},
                                    {kSource + "/docs/results/f40_levers/dpi_long_s1.pt", false},
                                    {kSource + "/docs/results/f40_levers/pagat_student.pt", false}};
// The scene's whole leak (3 s of oil from 3 s, when the river has settled) and the 2 s after
// it, in frames of 0.2 s, as the whole-leak test trajectories have it.
constexpr double kFrameDt = 0.2, kLeakStart = 3.0;
const std::vector<std::string> kWholeLeak = {"/output/frame_dt=0.2"};

nlohmann::json read_json(const fs::path& file) {
  std::ifstream in(file);
  return nlohmann::json::parse(in);
}

// Active fluid particles per frame of a run folder's trajectory.
std::vector<int64_t> active_counts(const gnn::Trajectory& t) {
  std::vector<int64_t> counts;
  for (int64_t k = 0; k < t.frames(); ++k) counts.push_back(t.active[k].sum().item<int64_t>());
  return counts;
}

}  // namespace

TEST(WaterBalance, EveryModelKeepsTheRiversWaterAndItsOilOverAWholeLeak) {
  const fs::path dir =
      fs::temp_directory_path() / ("spill_water_balance_" + std::to_string(getpid()));
  fs::remove_all(dir);
  sph::RunOptions simulated;
  simulated.out_dir = dir / "simulated";
  simulated.save_state_at = kLeakStart;
  sph::run_scene(sph::load_scene(kRiverSmall, kWholeLeak), simulated);
  const gnn::Trajectory sph_run = run_folder::read(dir / "simulated", dir / "view_sph").trajectory;
  // The SPH frames from the leak's start on.
  const int64_t first = std::lround(kLeakStart / kFrameDt);
  std::vector<int64_t> sph_active = active_counts(sph_run);
  sph_active.erase(sph_active.begin(), sph_active.begin() + first);
  const double volume = 0.05 * 0.05 * 0.05;  // a particle of radius 0.025 m

  for (size_t m = 0; m < kModels.size(); ++m) {
    SCOPED_TRACE(kModels[m].checkpoint);
    const fs::path out = dir / ("predicted_" + std::to_string(m));
    infer::PredictOptions o;
    o.checkpoint = kModels[m].checkpoint;
    o.scene_file = kRiverSmall;
    o.out_dir = out.string();
    o.overrides = kWholeLeak;
    o.initial_state = (dir / "simulated" / "state.h5").string();
    o.threads = 1;
    const nlohmann::json summary = infer::run_predict(o);
    EXPECT_EQ(summary["flow"]["skipped_inflow_layers"], 0);

    const gnn::Trajectory t = run_folder::read(out, dir / ("view_" + std::to_string(m))).trajectory;
    const std::vector<int64_t> active = active_counts(t);
    ASSERT_EQ(active.size(), sph_active.size());
    const nlohmann::json frames = read_json(out / "stats.json")["frames"];
    const nlohmann::json spill = read_json(out / "spill.json")["frames"];
    ASSERT_EQ(frames.size(), active.size());
    ASSERT_EQ(spill.size(), active.size());
    double worst_share = 0, worst_budget = 0, left = 0;
    for (size_t k = 0; k < active.size(); ++k) {
      const double share = std::abs(double(active[k] - sph_active[k])) / double(sph_active[k]);
      worst_share = std::max(worst_share, share);
      if (kModels[m].holds_the_count) {
        EXPECT_LE(share, 0.05) << "frame " << k << ": " << active[k] << " active against SPH's "
                               << sph_active[k];
      }
      // The oil on the water, by its fraction, plus what left the reach, is what was released.
      const auto on = t.active[int64_t(k)];
      const double on_water =
          t.oil_fraction[int64_t(k)].index({on}).to(torch::kFloat64).sum().item<double>() * volume;
      if (k > 0) left = frames[k]["oil_left_m3"].get<double>();
      const double released = spill[k]["oil_released_m3"].get<double>();
      worst_budget = std::max(worst_budget, std::abs(on_water + left - released));
      EXPECT_NEAR(on_water + left, released, volume) << "frame " << k;
    }
    // The leak released oil and some of it left: the budget had something to close.
    EXPECT_GT(spill.back()["oil_released_m3"].get<double>(), 0.004 * 3.0 - volume);
    EXPECT_GT(left, 0.0);
    std::cout << kModels[m].checkpoint << ": active within " << worst_share * 100
              << " % of SPH's at every frame; oil budget closes to " << worst_budget / volume
              << " particle volumes\n";
  }
  fs::remove_all(dir);
}
