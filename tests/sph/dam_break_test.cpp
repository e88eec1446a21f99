// Dam-break validation against the experiment of
//   J. C. Martin and W. J. Moyce, "An experimental study of the collapse of liquid columns on a
//   rigid horizontal plane", Phil. Trans. R. Soc. Lond. A 244 (1952) 312-324, Table 2:
//   surge front Z = x/a against T = t sqrt(2g/a) for a column of width a = 2.25 in and height
//   2a (n^2 = 2).
// The same points are tabulated in public validation scripts (e.g. Ocellaris'
// scripts/plot_dam_break.py, "Table 2 and 6"; Lethe's dam-break example), and agree within
// 0.05 in T with PySPH's independent reading of the paper's Figure 3.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "sph/scene/scene_loader.h"
#include "sph/simulation/simulation.h"
#include "tests/sph/fluid_measures.h"

namespace sph {
namespace {

struct Point {
  double T, Z;
};
// Martin & Moyce (1952), Table 2, n^2 = 2, a = 2.25 in.
const Point kMartinMoyce[] = {{0.41, 1.11}, {0.84, 1.22}, {1.19, 1.44}, {1.43, 1.67}, {1.63, 1.89},
                              {1.83, 2.11}, {1.98, 2.33}, {2.20, 2.56}, {2.32, 2.78}, {2.51, 3.00},
                              {2.65, 3.22}, {2.83, 3.44}, {2.98, 3.67}, {3.11, 3.89}, {3.33, 4.11}};

struct DamBreakResult {
  double mean_relative_error = 0;  // of the front against Martin & Moyce, 0.5 <= T <= 3.4
  std::string table;
  double mass_start = 0, mass_end = 0;  // kg
  Index particles_start = 0, particles_end = 0;
  double interior_density_error = 0;  // mean rho/rho0 - 1 away from the free surface
};

using testing_support::total_mass;

DamBreakResult run_martin_moyce(const std::vector<std::string>& overrides) {
  const LoadedScene scene =
      load_scene(std::string(SPILL_SOURCE_DIR) + "/configs/scenes/dam_break_mm.json", overrides);
  const SceneConfig& s = scene.config;
  const double wall = double(s.fluid_blocks[0].min[0]);
  const double a = double(s.fluid_blocks[0].max[0]) - wall;
  const double height = double(s.fluid_blocks[0].max[2] - s.fluid_blocks[0].min[2]);
  EXPECT_NEAR(height, 2 * a, 1e-6) << "the experiment is the n^2 = 2 column";
  const double g = -double(s.gravity[2]);
  const double time_scale = std::sqrt(a / (2 * g));  // t = T * time_scale

  Simulation sim(s);
  DamBreakResult result;
  result.mass_start = total_mass(sim.fluid());
  result.particles_start = sim.fluid().active_count();
  // Front: the largest x reached by the fluid (particle centre + radius), from the left wall.
  auto front = [&] {
    double x = -1e9;
    for (Index i = 0; i < sim.fluid().active_count(); ++i)
      x = std::max(x, double(sim.fluid().position[i][0]));
    return (x + double(s.particle_radius) - wall) / a;
  };
  double error_sum = 0;
  int compared = 0;
  int frame = 0;
  for (const Point& p : kMartinMoyce) {
    sim.advance_to(p.T * time_scale, ++frame);
    const double z = front();
    result.table += "T " + std::to_string(p.T) + ": Z sim " + std::to_string(z) + ", experiment " +
                    std::to_string(p.Z) + "\n";
    if (p.T < 0.5 || p.T > 3.4) continue;
    error_sum += std::abs(z - p.Z) / p.Z;
    ++compared;
  }
  result.mean_relative_error = error_sum / compared;
  const FluidParticles& f = sim.fluid();
  result.mass_end = total_mass(f);
  result.particles_end = f.active_count();
  // Compression at the end: the mean of rho/rho0 - 1 over the particles whose kernel sum is at
  // least 0.95 (the free-surface particles' sums are truncated, not expanded).
  double compression = 0;
  long inside = 0;
  for (Index i = 0; i < f.active_count(); ++i)
    if (f.density[i] >= Real(0.95)) {
      compression += double(f.density[i]) - 1;
      ++inside;
    }
  result.interior_density_error = inside > 0 ? compression / double(inside) : 1;
  return result;
}

// Every solver on the same experiment with the scene's settings and DFSPH's 10 % tolerance for
// the front (measured mean errors: DFSPH 6.6 %, MTDF-SPH 5.5 %, IISPH 6.9 %, PBF 7.2 %, WCSPH
// 5.9 %, PF-SPH 5.9 %: none needs a looser one), and mass and volume: no particle is lost, the
// total mass stays to float rounding, and the water away from the free surface is compressed by
// less than 1 % at the end (measured: between -0.7 % and -0.1 %, i.e. not compressed).
class DamBreakBySolver : public ::testing::TestWithParam<std::string> {};

TEST_P(DamBreakBySolver, FrontFollowsMartinMoyceAndMassIsConserved) {
  const DamBreakResult r = run_martin_moyce({"/solver=" + GetParam()});
  std::cout << r.table << "mean relative error " << r.mean_relative_error << ", mass "
            << r.mass_start << " -> " << r.mass_end << " kg, compression "
            << r.interior_density_error * 100 << " %\n";
  EXPECT_LT(r.mean_relative_error, 0.10) << r.table;
  EXPECT_EQ(r.particles_end, r.particles_start);
  EXPECT_NEAR(r.mass_end, r.mass_start, 1e-6 * r.mass_start);
  EXPECT_LT(r.interior_density_error, 0.01);
}

INSTANTIATE_TEST_SUITE_P(AllSolvers, DamBreakBySolver, ::testing::ValuesIn(pressure_solver_names()),
                         [](const auto& info) { return info.param; });

// PBF updates its constraints between iterations to first order in the corrections instead of
// re-evaluating every kernel (pbf_solver.h; the update itself is checked against re-evaluated
// densities in PressureTerms.DensityChangeIsTheFirstOrderChangeOfTheDensity). The collapsing
// column of the dam break with both schemes for 0.1 s (about 45 steps, up to 1.7 m/s): a
// collapse amplifies any difference (after 0.02 s the two runs differ by 5e-4 d at the median
// and 0.02 d at most; after 0.1 s by 0.015 d and 1.2 d at a splashing particle), so the bar is
// on the bulk: the median particle within 0.05 d of the paper's scheme and the mean compression
// within 10 % of it (measured 0.445 % against 0.425 %). (With the update's sign flipped the run
// does not reach 0.1 s.)
TEST(PbfConstraintUpdates, FirstOrderUpdatesMatchReevaluatedKernels) {
  const std::string file = std::string(SPILL_SOURCE_DIR) + "/configs/scenes/dam_break_mm.json";
  auto run = [&](bool every_iteration) {
    const LoadedScene scene =
        load_scene(file, {"/solver=\"pbf\"", std::string("/pbf/kernels_every_iteration=") +
                                                 (every_iteration ? "true" : "false")});
    auto sim = std::make_unique<Simulation>(scene.config);
    for (int frame = 1; frame <= 5; ++frame) sim->advance_to(0.02 * frame, frame);
    return sim;
  };
  const auto exact = run(true);
  const auto first_order = run(false);
  const FluidParticles& a = exact->fluid();
  const FluidParticles& b = first_order->fluid();
  ASSERT_EQ(a.active_count(), b.active_count());
  // The particles are kept sorted by grid cell, so the same index need not be the same particle.
  std::vector<Index> slot_of_id(a.size());
  for (Index i = 0; i < b.active_count(); ++i) slot_of_id[b.id[i]] = i;
  const double d = 2 * double(load_scene(file).config.particle_radius);
  std::vector<double> shift;
  double error_a = 0, error_b = 0, fastest = 0;
  for (Index i = 0; i < a.active_count(); ++i) {
    shift.push_back(double((a.position[i] - b.position[slot_of_id[a.id[i]]]).norm()) / d);
    error_a += std::max(double(a.density[i]) - 1, 0.0) / double(a.active_count());
    error_b += std::max(double(b.density[i]) - 1, 0.0) / double(b.active_count());
    fastest = std::max(fastest, double(a.velocity[i].norm()));
  }
  std::sort(shift.begin(), shift.end());
  const double median_shift = shift[shift.size() / 2];
  std::cout << "position difference: median " << median_shift << " d, largest " << shift.back()
            << " d; mean compression " << error_a * 100 << " % (kernels every iteration), "
            << error_b * 100 << " % (first order); fastest particle " << fastest << " m/s\n";
  EXPECT_GT(fastest, 1.0) << "the column should be collapsing";
  EXPECT_LT(median_shift, 0.05);
  EXPECT_NEAR(error_b, error_a, 0.1 * error_a);
}

}  // namespace
}  // namespace sph
