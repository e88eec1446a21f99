// A learned near field feeds the far field (issue 49): spill-infer predict, run on a near-field
// scene inside a reach run (the flume of tests/sph/flume_reach.h, at the particle radius and frame
// interval DPI-Nets was trained at), writes a folder that the far field's hand-over reads as it
// reads spill-sim run's (`/near_field/run`): every bit of the learned near field's oil, out of the
// box or still in it, becomes the far field's, and the forecast.json's hand-over names the model.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "farfield/forecast_run.h"
#include "infer/commands.h"
#include "sim/far_field_parcels.h"
#include "sph/app/near_field_handover.h"
#include "tests/sph/flume_reach.h"

namespace fs = std::filesystem;

namespace {

const std::string kDpi = std::string(SPILL_SOURCE_DIR) + "/docs/results/baselines/dpi.pt";

TEST(LearnedNearField, APredictFolderHandsItsOilToTheFarField) {
  const fs::path dir =
      fs::temp_directory_path() / ("spill_learned_near_field_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  flume_reach::run(dir);
  nlohmann::json scene = flume_reach::scene();
  scene["particle_radius"] = 0.025;  // DPI-Nets' data
  scene["terrain"]["reach"]["cell_size"] = 0.025;
  scene["end_time"] = 1.5;
  const double rate = 0.002, duration = 0.5;
  scene["leaks"] = flume_reach::leaks(rate, duration);
  std::ofstream(dir / "leak_scene.json") << scene.dump(2);
  infer::PredictOptions o;
  o.checkpoint = kDpi;
  o.scene_file = (dir / "leak_scene.json").string();
  o.out_dir = (dir / "learned").string();
  o.threads = 1;
  infer::run_predict(o);

  const sph::NearFieldHandover near = sph::near_field_handover_from_run(
      (dir / "learned").string(),
      {(dir / "flume_run").string(), "forecast.json", "/near_field/run"}, nullptr, false);
  EXPECT_EQ(near.summary["predicted_by"]["model"], "dpi");
  ASSERT_FALSE(near.parcels.empty());
  // The learned near field's oil is the leak's (its fraction update conserves the oil), to one
  // particle's volume.
  EXPECT_NEAR(near.left_m3 + near.remaining_m3, rate * duration, near.particle_volume_m3);
  double parcels = 0;
  for (const sph::NearFieldParcel& p : near.parcels) {
    parcels += p.volume;
    EXPECT_NEAR(p.x, flume_reach::kX0 + 8, 1.5);
    EXPECT_NEAR(p.y, flume_reach::kY0 + 1.2, 1.5);
  }

  // The far field releases exactly that oil.
  const nlohmann::json forecast =
      flume_reach::forecast({{"run", "learned"}, {"elements_per_parcel", 2}});
  std::ofstream(dir / "forecast.json") << forecast.dump(2);
  farfield::ForecastRunOptions run;
  run.config_file = (dir / "forecast.json").string();
  run.out_dir = (dir / "forecast_out").string();
  run.pictures = false;
  run.handover = sim::far_field_parcels(near.parcels);
  run.handover_summary = near.summary;
  const nlohmann::json summary = farfield::run_forecast(run);
  EXPECT_NEAR(summary["handover"]["volume_m3"].get<double>(), parcels, 1e-12);
  EXPECT_EQ(summary["elements"].get<size_t>(), 2 * near.parcels.size());
  EXPECT_EQ(summary["handover"]["near_field"]["predicted_by"]["model"], "dpi");
  fs::remove_all(dir);
}

}  // namespace
