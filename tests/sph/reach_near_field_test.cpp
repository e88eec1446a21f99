// A MTDF-SPH near field inside a reach run (terrain source "reach",
// sph/near_field/reach_terrain.h): a trapezoidal flume written as a GeoTIFF runs to its steady
// state in the shallow-water solver (tests/sph/flume_reach.h), and a 2 m box of it becomes an SPH
// scene whose terrain, water and inflow come from the run. The near field's water flows into the
// box at the reach's depth-averaged velocity there.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "common/config_error.h"
#include "farfield/forecast_run.h"
#include "reach/raster.h"
#include "reach/reach_run.h"
#include "sim/far_field_parcels.h"
#include "sph/app/near_field_handover.h"
#include "sph/app/scene_runner.h"
#include "sph/scene/scene_loader.h"
#include "sph/simulation/simulation.h"
#include "tests/sph/flume_reach.h"

namespace fs = std::filesystem;

namespace sph {
namespace {

using flume_reach::kDischarge;
using flume_reach::kX0;
using flume_reach::kY0;

class ReachNearField : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("spill_reach_near_field_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    summary_ = flume_reach::run(dir_);
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }

  static nlohmann::json scene_json() { return flume_reach::scene(); }
  static LoadedScene load(const nlohmann::json& scene) {
    std::ofstream(dir_ / "scene.json") << scene.dump(2);
    return load_scene((dir_ / "scene.json").string());
  }
  // The message of the ConfigError loading throws ("" when none).
  static std::string refusal(const nlohmann::json& scene) {
    try {
      load(scene);
    } catch (const common::ConfigError& e) {
      return e.what();
    }
    return "";
  }

  static fs::path dir_;
  static nlohmann::json summary_;
};

fs::path ReachNearField::dir_;
nlohmann::json ReachNearField::summary_;

}  // namespace

// The reach's depth-averaged velocity at the box's inflow, from its depth raster alone: the
// discharge over the wetted area of the cross-section there. After 1.5 s the SPH water just
// downstream of the inflow buffer moves at it within 10 %, and the scene's terrain is the flume's
// bed less the reach's water level.
TEST_F(ReachNearField, TheNearFieldFlowsInAtTheReachsVelocity) {
  ASSERT_TRUE(summary_["steady"]["reached"].get<bool>()) << summary_["steady"].dump();
  const auto& last = summary_["frames"].back();
  const reach::Raster depth =
      reach::read_raster((dir_ / "flume_run" / last["files"]["depth"].get<std::string>()).string());
  const reach::Grid& g = depth.grid;
  const int column = int((8 - 1 + 0.025) / g.dx);
  double area = 0, level = 0;
  int wet = 0;
  for (int j = 0; j < g.ny; ++j) {
    const double h = depth.values[g.at(column, j)];
    if (!(h > 0.01)) continue;
    area += h * g.dy;
    level += h + flume_reach::bed(g.x(column) - kX0, g.y(j) - kY0);
    ++wet;
  }
  level /= wet;
  const double reach_velocity = kDischarge / area;

  const LoadedScene scene = load(scene_json());
  const FlowConfig& flow = *scene.config.flow;
  const Terrain& terrain = *scene.config.terrain_grid;
  // The box's +x runs east with the flume, its z = 0 is the reach's level at the inflow.
  EXPECT_NEAR(double(scene.config.terrain->reach->heading), 90, 1);
  EXPECT_NEAR(double(terrain.height_at(1, 0)), flume_reach::bed(8, 1.2) - level, 0.01);
  EXPECT_NEAR(double(terrain.height_at(1, 0.6)), flume_reach::bed(8, 1.8) - level, 0.01);
  // The box's sides are walls: above the water however wide the flume's water is there.
  for (Real y : {terrain.origin_y, terrain.max_y()}) {
    EXPECT_GT(double(terrain.height_at(1, y)), 0.05) << y;
    EXPECT_FALSE(terrain.is_water(1, y)) << y;
  }
  EXPECT_TRUE(flow.plug);

  Simulation sim(scene.config);
  const double frame_dt = double(scene.config.output.frame_dt);
  const Real from = flow.inflow_x + flow.buffer, to = from + Real(0.5);
  double sum = 0;
  long samples = 0;
  for (int frame = 1; frame <= 60; ++frame) {
    sim.advance_to(frame * frame_dt, frame);
    if (frame * frame_dt < 1.5) continue;
    const FluidParticles& f = sim.fluid();
    for (Index i = 0; i < f.active_count(); ++i)
      if (f.position[i].x() > from && f.position[i].x() < to) {
        sum += double(f.velocity[i].x());
        ++samples;
      }
  }
  const double near_velocity = sum / double(samples);
  std::cout << "reach: depth-averaged velocity " << reach_velocity << " m/s over " << area
            << " m^2 at level " << level << " m; scene inflow speed " << flow.speed
            << " m/s; near field's mean over 1.5-3 s: " << near_velocity << " m/s ("
            << sim.fluid().active_count() << " particles active)\n";
  EXPECT_NEAR(near_velocity, reach_velocity, 0.1 * reach_velocity);
}

// A box narrower than the river (0.6 m across the flume's 0.8 m bed, so water reaches both of its
// sides): its sides are walls, no water leaves over them, and the water still flows at the
// reach's speed. Without the walls the water ran off the terrain's edges.
TEST_F(ReachNearField, ABoxNarrowerThanTheRiverIsWalledAlongItsSides) {
  nlohmann::json s = scene_json();
  s["terrain"]["reach"]["width"] = 0.6;
  const LoadedScene scene = load(s);
  const Terrain& terrain = *scene.config.terrain_grid;
  EXPECT_TRUE(terrain.is_water(1, 0));
  Simulation sim(scene.config);
  const FlowConfig& flow = *scene.config.flow;
  const double frame_dt = double(scene.config.output.frame_dt);
  double sum = 0;
  long samples = 0;
  for (int frame = 1; frame <= 30; ++frame) {
    sim.advance_to(frame * frame_dt, frame);
    if (frame * frame_dt < 1) continue;
    const FluidParticles& f = sim.fluid();
    for (Index i = 0; i < f.active_count(); ++i) {
      ASSERT_GT(f.position[i].y(), terrain.origin_y) << "frame " << frame;
      ASSERT_LT(f.position[i].y(), terrain.max_y()) << "frame " << frame;
      if (f.position[i].x() > flow.inflow_x + flow.buffer && f.position[i].x() < Real(1.5)) {
        sum += double(f.velocity[i].x());
        ++samples;
      }
    }
  }
  EXPECT_EQ(sim.flow()->fallen(), 0);
  EXPECT_NEAR(sum / double(samples), double(flow.speed), 0.1 * double(flow.speed));
}

// The shipped near field (configs/near_field/white_river_leak.json) reads strictly: with its
// reach run made (runs/white_river_steady) it loads; without it, the only complaint is the run.
TEST(ReachNearFieldConfig, TheShippedWhiteRiverLeakLoadsOrNamesItsMissingRun) {
  const std::string file =
      std::string(SPILL_SOURCE_DIR) + "/configs/near_field/white_river_leak.json";
  const bool run_made =
      fs::exists(std::string(SPILL_SOURCE_DIR) + "/runs/white_river_steady/reach.json");
  try {
    const LoadedScene scene = load_scene(file);
    EXPECT_TRUE(run_made);
    EXPECT_NEAR(double(scene.config.terrain->reach->heading), 224, 1);
    EXPECT_TRUE(scene.config.flow->plug);
  } catch (const common::ConfigError& e) {
    EXPECT_FALSE(run_made) << e.what();
    EXPECT_EQ(e.pointer(), "/terrain/reach/run") << e.what();
  }
}

// What the reach gives may be left out or given as it is; anything else is refused, naming the
// key, as is a box off the reach.
TEST_F(ReachNearField, RefusesSettingsTheReachGivesAndABoxOffIt) {
  const LoadedScene scene = load(scene_json());
  nlohmann::json s = scene_json();
  s["flow"]["speed"] = 2.0;
  EXPECT_NE(refusal(s).find("/flow/speed: comes from the reach run"), std::string::npos);
  s["flow"]["speed"] = scene.config.flow->speed;
  EXPECT_EQ(refusal(s), "");
  s = scene_json();
  s["terrain"]["water_level"] = 0.3;
  EXPECT_NE(refusal(s).find("/terrain/water_level"), std::string::npos);
  s = scene_json();
  s["terrain"]["reach"]["centre"] = {kX0 + 15.5, kY0 + 1.2};
  EXPECT_NE(refusal(s).find("/terrain/reach/centre: the box's corner"), std::string::npos);
  // The inflow buffer must outreach the kernel (support 0.08 m + spacing 0.04 m here); the plug
  // is on unless given.
  s = scene_json();
  s["flow"]["buffer"] = 0.1;
  EXPECT_NE(refusal(s).find("/flow/buffer: expected at least the kernel's support plus a particle "
                            "spacing (0.12 m)"),
            std::string::npos)
      << refusal(s);
  s = scene_json();
  s["flow"]["plug"] = false;
  EXPECT_EQ(refusal(s), "");
  EXPECT_FALSE(load(s).config.flow->plug);
  s = scene_json();
  s["terrain"]["reach"]["run"] = "nowhere";
  EXPECT_NE(refusal(s).find("/terrain/reach/run"), std::string::npos);
  // The resolved scene (as a run's metadata keeps it) loads again to the same box, from another
  // folder; its heading and time are written to the resolved scene's precision.
  const LoadedScene again = parse_scene(scene.resolved, (dir_ / "elsewhere" / "x.json").string());
  const auto& h0 = scene.config.terrain_grid->height;
  const auto& h1 = again.config.terrain_grid->height;
  ASSERT_EQ(h0.size(), h1.size());
  for (size_t k = 0; k < h0.size(); ++k) ASSERT_NEAR(double(h0[k]), double(h1[k]), 1e-5) << k;
  EXPECT_NEAR(double(again.config.flow->speed), double(scene.config.flow->speed), 1e-5);
}

// The near field's oil handed over to the far field (sph/app/near_field_handover.h): a leak in
// the flume's box from 0.2 s to 0.7 s, the box run to 2 s; the oil that left the box and the oil
// still in it add up to what the leak's schedule released, to one particle's volume, some of it
// having left through the outflow; and the far field, given those parcels, releases exactly their
// oil.
TEST_F(ReachNearField, TheOilHandedOverIsTheOilThatLeftOrRemainsInTheBox) {
  nlohmann::json scene = scene_json();
  scene["end_time"] = 2.0;  // the leak's first oil leaves the box from 1.7 s, its last by 2.4 s
  const double rate = 0.002, duration = 0.5;
  scene["leaks"] = flume_reach::leaks(rate, duration);
  std::ofstream(dir_ / "leak_scene.json") << scene.dump(2);
  // A far field on another reach run (here a copy of the flume's) is refused before any SPH.
  fs::copy(dir_ / "flume_run", dir_ / "other_run", fs::copy_options::recursive);
  try {
    run_near_field_handover((dir_ / "leak_scene.json").string(), {},
                            {(dir_ / "other_run").string(), "forecast.json", "/near_field/scene"},
                            nullptr, nullptr, false);
    ADD_FAILURE() << "a near field in another reach run than the far field's was accepted";
  } catch (const common::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("forecast.json:/near_field/scene"), std::string::npos)
        << e.what();
  }
  const NearFieldHandover near =
      run_near_field_handover((dir_ / "leak_scene.json").string(), {},
                              {(dir_ / "flume_run").string(), "forecast.json", "/near_field/scene"},
                              nullptr, nullptr, false);
  const double particle = std::pow(0.04, 3);
  // A particle's rest volume is the lattice's, d^3 to the kernel sum's error.
  ASSERT_NEAR(near.particle_volume_m3, particle, 1e-4 * particle);
  EXPECT_NEAR(near.left_m3 + near.remaining_m3, rate * duration, particle);
  EXPECT_GT(near.left_m3, 0) << "no oil left the box in 2 s";
  EXPECT_GT(near.remaining_m3, 0);
  double parcels = 0;
  for (const NearFieldParcel& p : near.parcels) {
    parcels += p.volume;
    // Map coordinates inside the box's footprint around (kX0 + 8, kY0 + 1.2).
    EXPECT_NEAR(p.x, kX0 + 8, 1.5);
    EXPECT_NEAR(p.y, kY0 + 1.2, 1.5);
    if (p.left) {
      EXPECT_GT(p.x, kX0 + 8 + 0.5) << "oil left the box upstream of its outflow";
    }
  }
  EXPECT_NEAR(parcels, near.left_m3 + near.remaining_m3, 1e-12);

  // The far field takes them over on the flume's flow: every cubic metre, at its density.
  const nlohmann::json forecast =
      flume_reach::forecast({{"scene", "leak_scene.json"}, {"elements_per_parcel", 3}});
  std::ofstream(dir_ / "forecast.json") << forecast.dump(2);
  farfield::ForecastRunOptions o;
  o.config_file = (dir_ / "forecast.json").string();
  o.out_dir = (dir_ / "forecast_out").string();
  o.pictures = false;
  o.handover = sim::far_field_parcels(near.parcels);
  const nlohmann::json summary = farfield::run_forecast(o);
  const double density = summary["outputs"].back()["budget_kg"]["released"].get<double>() /
                         summary["handover"]["volume_m3"].get<double>();
  EXPECT_NEAR(summary["handover"]["volume_m3"].get<double>(), parcels, 1e-12);
  EXPECT_NEAR(density, 863.9, 1e-9 * 863.9);
  EXPECT_EQ(summary["elements"].get<size_t>(), 3 * near.parcels.size());
}

// The same hand-over from the run folder `spill-sim run` writes of the scene (a learned near
// field's, from spill-infer predict, has the same layout): trajectory.h5 records the frames the
// in-process hand-over meets, so the parcels are the same, to the last bit. A folder that is not
// a finished run is refused naming the forecast's key, a corrupt trajectory naming the file.
TEST_F(ReachNearField, AFinishedRunFolderHandsOverTheSameOilAsRunningItsScene) {
  nlohmann::json scene = scene_json();
  scene["end_time"] = 2.0;
  scene["leaks"] = flume_reach::leaks(0.002, 0.5);
  std::ofstream(dir_ / "leak_scene.json") << scene.dump(2);
  const FarFieldReachRun far_field{(dir_ / "flume_run").string(), "forecast.json",
                                   "/near_field/run"};
  const NearFieldHandover ran = run_near_field_handover((dir_ / "leak_scene.json").string(), {},
                                                        far_field, nullptr, nullptr, false);
  RunOptions options;
  options.out_dir = dir_ / "near_run";
  run_scene(load_scene((dir_ / "leak_scene.json").string()), options);
  const NearFieldHandover read =
      near_field_handover_from_run((dir_ / "near_run").string(), far_field, nullptr, false);

  ASSERT_GT(ran.parcels.size(), 10u);
  ASSERT_EQ(read.parcels.size(), ran.parcels.size());
  for (size_t k = 0; k < ran.parcels.size(); ++k) {
    const NearFieldParcel &a = ran.parcels[k], &b = read.parcels[k];
    EXPECT_EQ(a.t, b.t) << k;
    EXPECT_EQ(a.x, b.x) << k;
    EXPECT_EQ(a.y, b.y) << k;
    EXPECT_EQ(a.volume, b.volume) << k;
    EXPECT_EQ(a.area, b.area) << k;
    EXPECT_EQ(a.left, b.left) << k;
  }
  EXPECT_EQ(read.left_m3, ran.left_m3);
  EXPECT_EQ(read.remaining_m3, ran.remaining_m3);
  EXPECT_GT(read.left_m3, 0);
  EXPECT_EQ(read.summary["run"], (dir_ / "near_run").string());
  // A learned near field's folder (spill-infer predict's) says which model predicted it: so does
  // the hand-over's summary, in forecast.json.
  nlohmann::json metadata;
  std::ifstream(dir_ / "near_run" / "metadata.json") >> metadata;
  metadata["predicted_by"] = {{"model", "dpi"}};
  std::ofstream(dir_ / "near_run" / "metadata.json") << metadata.dump();
  EXPECT_EQ(near_field_handover_from_run((dir_ / "near_run").string(), far_field, nullptr, false)
                .summary["predicted_by"]["model"],
            "dpi");

  // Not a run: an empty folder; a run in another reach run; a trajectory cut short.
  fs::create_directories(dir_ / "empty");
  const auto refusal = [&](const fs::path& folder, const FarFieldReachRun& field) {
    try {
      near_field_handover_from_run(folder.string(), field, nullptr, false);
    } catch (const common::InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(refusal(dir_ / "empty", far_field).find("forecast.json:/near_field/run"),
            std::string::npos);
  fs::copy(dir_ / "flume_run", dir_ / "another_reach_run", fs::copy_options::recursive);
  EXPECT_NE(refusal(dir_ / "near_run",
                    {(dir_ / "another_reach_run").string(), "forecast.json", "/near_field/run"})
                .find("forecast.json:/near_field/run"),
            std::string::npos);
  fs::resize_file(dir_ / "near_run" / "trajectory.h5",
                  fs::file_size(dir_ / "near_run" / "trajectory.h5") / 2);
  EXPECT_NE(refusal(dir_ / "near_run", far_field).find("trajectory.h5"), std::string::npos);
}

}  // namespace sph
