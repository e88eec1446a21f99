// Two-phase validation of MTDF-SPH: layering after a pour, conservation of mass and volume
// fractions, surface tension in zero gravity, an oil cube that rises without mixing, and
// immiscibility in a collision compared with plain DFSPH (the MTDF-SPH paper's Fig. 6 claim).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <sstream>

#include <Eigen/Eigenvalues>

#include "sph/scene/scene_loader.h"
#include "sph/simulation/simulation.h"
#include "tests/sph/fluid_measures.h"

namespace sph {
namespace {

const std::string kScenes = std::string(SPILL_SOURCE_DIR) + "/configs/scenes/";

void run_to(Simulation& sim, double t_end, double frame_dt) {
  const int frames = int(std::lround(t_end / frame_dt));
  for (int f = 1; f <= frames; ++f) sim.advance_to(double(f) * frame_dt, f);
}

bool is_oil(const FluidParticles& f, Index i) {
  return f.oil_fraction[i] >= Real(0.5);
}

// Pairs of active particles closer than `radius` whose dominant phases differ, and all pairs.
std::pair<long, long> unlike_pairs(const FluidParticles& f, double radius) {
  long unlike = 0, all = 0;
  const Index n = f.active_count();
  for (Index i = 0; i < n; ++i)
    for (Index j = i + 1; j < n; ++j)
      if (double((f.position[i] - f.position[j]).squaredNorm()) < radius * radius) {
        ++all;
        unlike += is_oil(f, i) != is_oil(f, j);
      }
  return {unlike, all};
}

using testing_support::total_mass;

// Ratio of the largest to the smallest principal radius of gyration of the active particles.
double gyration_ratio(const FluidParticles& f) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  const Index n = f.active_count();
  for (Index i = 0; i < n; ++i) mean += f.position[i].cast<double>();
  mean /= double(n);
  Eigen::Matrix3d c = Eigen::Matrix3d::Zero();
  for (Index i = 0; i < n; ++i) {
    const Eigen::Vector3d d = f.position[i].cast<double>() - mean;
    c += d * d.transpose() / double(n);
  }
  const Eigen::Vector3d ev = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(c).eigenvalues();
  return std::sqrt(ev.maxCoeff() / ev.minCoeff());
}

// Oil poured from a pipe plunges to the floor; after settling MTDF-SPH has it in a layer on
// top: >= 95 % of the oil particles above the water's free surface (the mean over 2d x 2d
// columns of the highest water particle) minus one diameter, and few water particles above
// the oil layer's lower quartile.
// Height of the oil's centre: the oil-fraction-weighted mean z of the fluid particles.
double oil_height(const FluidParticles& f) {
  double volume = 0, moment = 0;
  for (Index i = 0; i < f.active_count(); ++i) {
    volume += double(f.oil_fraction[i]);
    moment += double(f.oil_fraction[i]) * double(f.position[i][2]);
  }
  return moment / volume;
}

TEST(TwoPhase, PouredOilEndsInALayerOnTop) {
  const LoadedScene scene = load_scene(kScenes + "oil_water_pour.json");
  Simulation sim(scene.config);
  run_to(sim, double(scene.config.end_time), double(scene.config.output.frame_dt));
  const FluidParticles& f = sim.fluid();
  const double d = double(scene.config.particle_diameter());
  std::map<std::pair<int, int>, double> column_top;
  std::vector<double> oil_z;
  for (Index i = 0; i < f.active_count(); ++i) {
    const Vec3& x = f.position[i];
    if (is_oil(f, i)) {
      oil_z.push_back(double(x[2]));
      continue;
    }
    const auto key = std::make_pair(int(std::floor(double(x[0]) / (2 * d))),
                                    int(std::floor(double(x[1]) / (2 * d))));
    auto it = column_top.find(key);
    if (it == column_top.end() || it->second < double(x[2])) column_top[key] = double(x[2]);
  }
  double surface = 0;
  for (const auto& c : column_top) surface += c.second / double(column_top.size());
  const double above =
      double(std::count_if(oil_z.begin(), oil_z.end(), [&](double z) { return z > surface - d; })) /
      double(oil_z.size());
  std::sort(oil_z.begin(), oil_z.end());
  const double oil_lower_quartile = oil_z[oil_z.size() / 4];
  long water_above = 0;
  for (Index i = 0; i < f.active_count(); ++i)
    water_above += !is_oil(f, i) && double(f.position[i][2]) > oil_lower_quartile;
  std::ostringstream what;
  what << oil_z.size() << " oil particles, water surface " << surface
       << " m, oil above it - d: " << above * 100
       << " %, water particles above the oil's lower quartile: " << water_above;
  EXPECT_GE(oil_z.size(), 1400u) << what.str();  // 1,503 particles' worth of oil was poured
  EXPECT_GE(above, 0.95) << what.str();
  EXPECT_LT(double(water_above), 0.1 * double(oil_z.size())) << what.str();
}

// An oil cube under water, no emitter: the total mass stays constant to 1e-6 relative, every
// oil fraction stays in [0, 1] (water's is 1 - oil's, so the sum is 1 by construction) and the
// rest density matches the fractions; the oil rises.
TEST(TwoPhase, MixtureConservesMassAndBoundsFractions) {
  const LoadedScene scene =
      load_scene(kScenes + "oil_rise.json",
                 {"/solver=\"mtdf\"", "/particle_radius=0.02", "/end_time=1.5",
                  "/materials/water/viscosity=0.001", "/materials/oil/viscosity=0.004"});
  Simulation sim(scene.config);
  const double mass0 = total_mass(sim.fluid());
  const double height0 = oil_height(sim.fluid());
  double worst_mass = 0;
  const int frames = int(std::lround(scene.config.end_time / scene.config.output.frame_dt));
  for (int frame = 1; frame <= frames; ++frame) {
    sim.advance_to(double(frame) * double(scene.config.output.frame_dt), frame);
    const FluidParticles& f = sim.fluid();
    worst_mass = std::max(worst_mass, std::abs(total_mass(f) / mass0 - 1));
    for (Index i = 0; i < f.active_count(); ++i) {
      ASSERT_GE(f.oil_fraction[i], 0) << "frame " << frame << " particle " << i;
      ASSERT_LE(f.oil_fraction[i], 1) << "frame " << frame << " particle " << i;
      const double expected =
          double(scene.config.materials.oil.density) * f.oil_fraction[i] +
          double(scene.config.materials.water.density) * (1 - f.oil_fraction[i]);
      ASSERT_NEAR(f.rest_density[i], expected, 1e-3 * expected);
    }
  }
  EXPECT_LT(worst_mass, 1e-6);
  EXPECT_GT(oil_height(sim.fluid()) - height0, 0.05)
      << "oil-weighted height " << height0 << " -> " << oil_height(sim.fluid()) << " m";
}

// Zero gravity: a 2:1:1 block of water pulls itself toward a sphere under surface tension: the
// ratio of its principal radii of gyration, 2 at the start, approaches 1 (a sphere of 250
// particles stays a little lumpy and oscillates, so the bar is the mean over the last 3 s of
// 6 s). The same block with the force on every particle (surface_only off) is the control: the
// bulk's cohesion then holds the lattice together and it hardly rounds, so its ratio must stay
// at least 0.4 above the surface-only one (measured 2.17 against 1.19): the rounding comes from
// applying the force where the paper does, not from anything both runs share.
// With the reference oil's 4x viscosity the block jams near a ratio of 1.6.
TEST(TwoPhase, SurfaceTensionRoundsABlockInZeroGravity) {
  auto late_mean_ratio = [](bool surface_only, double* ratio0) {
    nlohmann::json j = nlohmann::json::parse(R"({
      "name": "zero_g_block", "solver": "mtdf", "particle_radius": 0.01, "end_time": 6.0,
      "gravity": [0, 0, 0], "output": {"frame_dt": 0.1},
      "materials": {"water": {"density": 1000, "viscosity": 0.001},
                    "oil": {"density": 940, "viscosity": 0.004}},
      "domain": {"min": [-0.3, -0.3, -0.3], "max": [0.5, 0.3, 0.3]},
      "fluid_blocks": [{"min": [0, -0.05, -0.05], "max": [0.2, 0.05, 0.05]}]})");
    j["surface_tension"]["surface_only"] = surface_only;
    Simulation sim(parse_scene(j, "zero_g_block").config);
    *ratio0 = gyration_ratio(sim.fluid());
    double late_mean = 0;
    for (int frame = 1; frame <= 60; ++frame) {
      sim.advance_to(0.1 * frame, frame);
      if (frame > 30) late_mean += gyration_ratio(sim.fluid()) / 30;
    }
    return late_mean;
  };
  double ratio0 = 0, ratio0_all = 0;
  const double surface = late_mean_ratio(true, &ratio0);
  const double all = late_mean_ratio(false, &ratio0_all);
  std::cout << "ratio of radii of gyration " << ratio0 << " -> mean over 3-6 s " << surface
            << " (force on surface particles), " << all << " (on all particles)\n";
  EXPECT_NEAR(ratio0, 2.0, 0.1);
  EXPECT_LT(surface, 1.3) << "ratio of radii of gyration " << ratio0 << " -> " << surface;
  EXPECT_GT(all - surface, 0.4) << "force on all particles " << all << ", on the surface "
                                << surface;
}

// Share of the oil volume held by oil-dominant particles (oil fraction >= 1/2): 1 while oil and
// water are apart, towards 0 when the oil is spread over the water as a dilute mixture.
double oil_volume_in_oil_particles(const FluidParticles& f) {
  double oil = 0, in_oil_particles = 0;
  for (Index i = 0; i < f.active_count(); ++i) {
    oil += double(f.oil_fraction[i]);
    if (is_oil(f, i)) in_oil_particles += double(f.oil_fraction[i]);
  }
  return in_oil_particles / oil;
}

// An oil cube (64 particles) in the middle of a closed 0.2 m box of water, with gravity: buoyancy
// drives the drift, which must carry the oil up: its oil-weighted height rises at least 5 cm in
// 1 s (measured 8.5 cm; with Ren's own-mixture slip, 1.3 cm), so the mixture model has had
// something to do. It moves the oil by exchanging fractions, so during the rise the oil is
// spread over up to 4x as many particles (share in oil-dominant particles down to 0.4 at 0.3 s);
// at the top the trace absorption and the drift gather it again. After 1 s at least 80 % of the
// oil volume must be in oil-dominant particles (measured 0.91). Control: 100 x the default
// diffusion (/mixture/diffusion_sigma 0.01 m^2/s) smears the oil over the water and must leave
// at most 50 % (measured 0.28). A count of unlike-phase neighbour pairs cannot
// tell these apart: a fully smeared cube has no oil-dominant particle left and so no such pair.
TEST(TwoPhase, RisingOilCubeStaysUnmixed) {
  auto run = [](double diffusion_sigma, double* rise) {
    nlohmann::json j = nlohmann::json::parse(R"({
      "name": "oil_cube_rising", "solver": "mtdf", "particle_radius": 0.01, "end_time": 1.0,
      "gravity": [0, 0, -9.81], "output": {"frame_dt": 0.1},
      "materials": {"water": {"density": 1000, "viscosity": 0.001},
                    "oil": {"density": 940, "viscosity": 0.004}},
      "boxes": [{"min": [0, 0, 0], "max": [0.2, 0.2, 0.2]}],
      "fluid_blocks": [{"min": [0.06, 0.06, 0.06], "max": [0.14, 0.14, 0.14], "material": "oil"},
                       {"min": [0, 0, 0], "max": [0.2, 0.2, 0.06]},
                       {"min": [0, 0, 0.14], "max": [0.2, 0.2, 0.2]},
                       {"min": [0, 0, 0.06], "max": [0.06, 0.2, 0.14]},
                       {"min": [0.14, 0, 0.06], "max": [0.2, 0.2, 0.14]},
                       {"min": [0.06, 0, 0.06], "max": [0.14, 0.06, 0.14]},
                       {"min": [0.06, 0.14, 0.06], "max": [0.14, 0.2, 0.14]}]})");
    j["mixture"]["diffusion_sigma"] = diffusion_sigma;
    Simulation sim(parse_scene(j, "oil_cube_rising").config);
    const double height0 = oil_height(sim.fluid());
    EXPECT_EQ(oil_volume_in_oil_particles(sim.fluid()), 1.0) << "the cube starts pure";
    run_to(sim, 1.0, 0.1);
    *rise = oil_height(sim.fluid()) - height0;
    return oil_volume_in_oil_particles(sim.fluid());
  };
  double rise = 0, rise_smeared = 0;      // m
  const double share = run(1e-4, &rise);  // the default diffusion_sigma
  std::cout << "oil volume in oil-dominant particles after 1 s: " << share << " (oil rose " << rise
            << " m)\n";
  EXPECT_GT(rise, 0.05) << "the drift should carry the oil up";
  EXPECT_GE(share, 0.8) << "oil rose " << rise << " m";
  const double smeared = run(1e-2, &rise_smeared);
  std::cout << "with 100 x the diffusion: " << smeared << " (oil rose " << rise_smeared << " m)\n";
  EXPECT_LE(smeared, 0.5) << "the control should mix";
}

// Water and oil injected from opposite walls collide: with plain DFSPH they interpenetrate, with
// MTDF-SPH they stay apart (unlike-phase neighbour pairs as a share of all pairs, at the end).
TEST(TwoPhase, CollidingPhasesStayApartWithMtdfButNotDfsph) {
  auto mixed_share = [&](const std::string& solver) {
    const LoadedScene scene =
        load_scene(kScenes + "two_phase_collision.json", {"/solver=\"" + solver + "\""});
    Simulation sim(scene.config);
    run_to(sim, double(scene.config.end_time), double(scene.config.output.frame_dt));
    const auto pairs = unlike_pairs(sim.fluid(), double(scene.config.support_radius()));
    return std::make_pair(double(pairs.first) / double(pairs.second), pairs.first);
  };
  const auto mtdf = mixed_share("mtdf");
  const auto dfsph = mixed_share("dfsph");
  std::ostringstream what;
  what << "unlike-phase pairs at the end: MTDF-SPH " << mtdf.second << " (" << mtdf.first * 100
       << " %), DFSPH " << dfsph.second << " (" << dfsph.first * 100 << " %)";
  EXPECT_LT(mtdf.first, 0.12) << what.str();
  EXPECT_GT(dfsph.first, 0.25) << what.str();
  EXPECT_LT(mtdf.first, dfsph.first / 3) << what.str();
  std::cout << what.str() << "\n";
}

}  // namespace
}  // namespace sph
