// Oil on still water, MTDF-SPH. Dropped onto the water (configs/scenes/slick_still_water.json),
// the slick thins to one layer of particles without contracting and stays one piece, and a
// made-up oil with a strongly negative spreading coefficient stays thicker. Released at its
// floating depth (slick_still_water_floating.json, Fay's set-up), it spreads at Fay's
// gravity-inertia exponent, and faster, towards Fay's rate, when the slick is resolved by more
// particles.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <vector>

#include "common/config_visitors.h"
#include "sph/river/fay_spreading.h"
#include "sph/river/slick_shape.h"
#include "sph/scene/scene_loader.h"
#include "sph/simulation/simulation.h"

namespace sph {
namespace {

const std::string kScenes = std::string(SPILL_SOURCE_DIR) + "/configs/scenes/";

struct SlickRun {
  std::vector<std::pair<double, SlickShape>> frames;
  double diameter = 0;
  double delta = 0;  // (rho_water - rho_oil) / rho_water
};

SlickRun run_slick(const std::string& scene_file, const std::vector<std::string>& overrides,
                   double end_time) {
  std::vector<std::string> set = overrides;
  set.push_back("/end_time=" + std::to_string(end_time));
  const LoadedScene scene = load_scene(kScenes + scene_file, set);
  Simulation sim(scene.config);
  SlickRun out;
  out.diameter = double(scene.config.particle_diameter());
  out.delta = 1 - double(scene.config.materials.oil.density / scene.config.materials.water.density);
  // Frames at spill-sim's times (0.05, not the float's 0.0500000007), so its runs and these agree.
  const double frame_dt = common::shortest_decimal(scene.config.output.frame_dt);
  const int frames = int(std::lround(end_time / frame_dt));
  for (int f = 0; f <= frames; ++f) {
    if (f > 0) sim.advance_to(frame_dt * f, f);
    out.frames.emplace_back(frame_dt * f,
                            measure_slick(sim.fluid(), scene.config.particle_diameter()));
  }
  return out;
}

// Dropped onto the water, the slick must thin to one layer: the water's top layer, oil or water,
// holds about 1.25 particles per diameter squared (the density solve corrects compression only,
// so a surface particle's kernel sum is short until its layer is crowded), so one complete layer
// reads 1.25 diameters of mean thickness; the bound is 1.4 (measured 1.34 at 2 s; with the river
// scenes' ten times larger viscosities the slick stopped at 1.6, about 6 cm, as it does at 2 cm
// particles: a viscous stall, not the resolution). It must never shrink by more than 10 % of its
// largest area so far (measured 4 %; the cohesion of the earlier surface-tension strengths pulled
// it from 0.45 back to 0.42 m^2), and stay one piece: at least 95 % of the oil in its largest
// patch (measured 99.2 %; the other patches are single-particle droplets). A made-up oil with an
// oil/water tension of 3 N/m (spreading coefficient -2.96 N/m) must end at least 10 % smaller
// (measured 0.46 against 0.60 m^2 at 2 s).
TEST(Slick,
     DroppedOnWaterItThinsToOneLayerInOnePieceAndANegativeSpreadingCoefficientKeepsItThicker) {
  const SlickRun crude = run_slick("slick_still_water.json", {}, 2.0);
  double largest = 0, worst_drop = 0;
  for (const auto& [t, s] : crude.frames) {
    largest = std::max(largest, s.area_m2);
    worst_drop = std::max(worst_drop, 1 - s.area_m2 / largest);
  }
  const SlickShape& end = crude.frames.back().second;
  std::cout << "dropped: at 2 s area " << end.area_m2 << " m^2, thickness "
            << end.mean_thickness_m / crude.diameter << " diameters, " << end.patches
            << " patch(es), the largest with " << end.largest_patch_share * 100
            << " % of the oil; largest drop " << worst_drop * 100 << " %\n";
  EXPECT_LT(worst_drop, 0.1);
  EXPECT_LT(end.mean_thickness_m, 1.4 * crude.diameter);
  EXPECT_GT(end.largest_patch_share, 0.95);

  const SlickRun lens = run_slick("slick_still_water.json", {"/surface_tension/oil_water=3"}, 2.0);
  std::cout << "oil/water tension 3 N/m: area " << lens.frames.back().second.area_m2
            << " m^2 against " << end.area_m2 << "\n";
  EXPECT_LT(lens.frames.back().second.area_m2, 0.9 * end.area_m2);
}

// Released at rest at its floating depth, only the oil's buoyancy drives the slick, so its
// growth is the model's: Fay's gravity-inertia law A - A0 = pi k1^2 (Delta g V)^(1/2) t^slope
// (Fay: slope 1, k1 1.14), fitted (sph/river/fay_spreading.h) from the frame where the slick has
// grown by a fifth to the last before it thins below two diameters. With 4 cm particles (a
// slick 5 particles thick at release) the slope is 1.01 over 0.4-1.6 s and k1 0.61; with 2 cm
// particles (10 thick) 1.09 and 0.74 over 0.3-2 s (2.5 minutes); docs/results/slick_resolution.md
// adds 1.33 cm (0.80). Bounds: the slope within 25 % of Fay's at both sizes, and k1 at least 10 %
// larger at 2 cm than at 4 cm: the rate converges towards Fay's from below as the slick is
// resolved.
TEST(Slick, FloatingOilSpreadsAtFaysExponentAndTowardsFaysRateWithResolution) {
  std::vector<FayFit> fits;
  for (const char* radius : {"/particle_radius=0.02", "/particle_radius=0.01"}) {
    const SlickRun run = run_slick("slick_still_water_floating.json", {radius}, 2.0);
    const FayFit fit = fit_fay_gravity_inertia(run.frames, run.delta, 9.81, run.diameter);
    std::cout << radius << ": Fay fit over " << fit.window_start_s << "-" << fit.window_end_s
              << " s (" << fit.frames << " frames): slope " << fit.slope << ", k1 " << fit.k1
              << "\n";
    ASSERT_TRUE(fit.valid);
    EXPECT_NEAR(fit.slope, 1.0, 0.25);
    fits.push_back(fit);
  }
  EXPECT_GT(fits[1].k1, 1.1 * fits[0].k1);
}

}  // namespace
}  // namespace sph
