// Non-pressure forces on a small lattice with random velocities: viscosity and XSPH exchange
// momentum between pairs symmetrically (total momentum is conserved) and smooth the velocity
// field (its variance falls); gravity adds g to every particle; the surface tension, which reads
// its pair law from a table, agrees with the cosine law evaluated directly.

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>

#include "sph/core/lattice.h"
#include "sph/forces/gravity_force.h"
#include "sph/forces/surface_tension_force.h"
#include "sph/forces/viscosity_force.h"
#include "sph/forces/xsph_force.h"

namespace sph {
namespace {

struct Lattice {
  FluidParticles fluid;
  BoundaryParticles boundary;  // none: the forces act between fluid particles only
  std::unique_ptr<ParticleNeighbourhood> neighbourhood;
};

Lattice random_lattice() {
  const Real r = Real(0.05), h = 4 * r;
  Lattice l;
  const Real volume = lattice_rest_volume(KernelKind::kCubicSpline, h, 2 * r);
  std::mt19937 rng(3);
  std::normal_distribution<Real> n(0, 1);
  for (const Vec3& p : lattice_points(Vec3(0, 0, 0), Vec3(0.8f, 0.8f, 0.8f), 2 * r))
    l.fluid.add(p, Vec3(n(rng), n(rng), n(rng)), volume,
                mix_phases(0, 1000, Real(0.05), 940, Real(0.2)));
  const Aabb domain{Vec3::Constant(-h), Vec3::Constant(Real(0.8) + h)};
  l.neighbourhood =
      std::make_unique<ParticleNeighbourhood>(domain, KernelKind::kCubicSpline, h, l.boundary);
  l.neighbourhood->update(l.fluid, l.boundary);
  return l;
}

Vec3d momentum_change(const FluidParticles& f) {  // sum m a, in double
  Vec3d p = Vec3d::Zero();
  for (Index i = 0; i < f.size(); ++i)
    p += (double(f.rest_density[i] * f.rest_volume[i]) * f.acceleration[i].cast<double>());
  return p;
}

double variance_after(FluidParticles f, Real dt) {
  double sum = 0;
  Vec3d mean = Vec3d::Zero();
  for (Index i = 0; i < f.size(); ++i)
    mean += (f.velocity[i] + dt * f.acceleration[i]).cast<double>();
  mean /= double(f.size());
  for (Index i = 0; i < f.size(); ++i)
    sum += ((f.velocity[i] + dt * f.acceleration[i]).cast<double>() - mean).squaredNorm();
  return sum / double(f.size());
}

void expect_conserving_and_smoothing(NonPressureForce& force, Real dt) {
  Lattice l = random_lattice();
  const double before = variance_after(l.fluid, 0);
  force.add_acceleration(l.fluid, l.boundary, *l.neighbourhood, dt);
  double scale = 0;
  for (Index i = 0; i < l.fluid.size(); ++i)
    scale +=
        double(l.fluid.rest_density[i] * l.fluid.rest_volume[i] * l.fluid.acceleration[i].norm());
  ASSERT_GT(scale, 0);
  EXPECT_LT(momentum_change(l.fluid).norm(), 1e-4 * scale) << force.name();
  EXPECT_LT(variance_after(l.fluid, dt), 0.9 * before) << force.name();
}

TEST(Forces, ViscosityConservesMomentumAndSmooths) {
  ViscosityForce viscosity(0);  // the particles' own viscosity, 0.05 m^2/s
  expect_conserving_and_smoothing(viscosity, Real(0.01));
}

TEST(Forces, XsphConservesMomentumAndSmooths) {
  XsphForce xsph(Real(0.5));
  expect_conserving_and_smoothing(xsph, Real(0.01));
}

TEST(Forces, GravityAddsG) {
  Lattice l = random_lattice();
  GravityForce gravity(Vec3(0, 0, Real(-9.81)));
  gravity.add_acceleration(l.fluid, l.boundary, *l.neighbourhood, Real(0.01));
  for (Index i = 0; i < l.fluid.size(); ++i)
    EXPECT_EQ(l.fluid.acceleration[i], Vec3(0, 0, Real(-9.81)));
}

// a_i = (rho_ref / rho0_i) sum_j s_ij V_j cos(3 pi r / 2h) W(r) (x_i - x_j) / r in double, from
// the formula in surface_tension_force.h with the kernel's own value.
template <class Kernel>
std::vector<Vec3d> direct_surface_tension(const FluidParticles& f, const Kernel& w, double h,
                                          const PairStrengths& c, double rho_ref) {
  std::vector<Vec3d> a(f.size(), Vec3d::Zero());
  for (Index i = 0; i < f.size(); ++i)
    for (Index j = 0; j < f.size(); ++j) {
      const Vec3d xij = (f.position[i] - f.position[j]).cast<double>();
      const double r = xij.norm();
      if (i == j || r >= h) continue;
      const double s = f.type[i] != f.type[j]            ? c.oil_water
                       : f.type[i] == ParticleType::kOil ? c.oil
                                                         : c.water;
      const double law = std::cos(1.5 * M_PI * r / h) * double(w.value(Real(r))) / r;
      a[i] += (rho_ref / f.rest_density[i]) * s * f.rest_volume[j] * law * xij;
    }
  return a;
}

void expect_surface_tension_matches_the_cosine_law(KernelKind kernel) {
  // A jittered lattice (pair distances off the table's nodes) of oil and water in layers, so
  // that both like and unlike pairs act; every particle feels the force (surface_only false).
  const Real r = Real(0.05), h = 4 * r;
  FluidParticles fluid;
  std::mt19937 rng(5);
  std::uniform_real_distribution<Real> jitter(-Real(0.3) * r, Real(0.3) * r);
  const Real volume = lattice_rest_volume(kernel, h, 2 * r);
  for (const Vec3& p : lattice_points(Vec3(0, 0, 0), Vec3(0.6f, 0.6f, 0.6f), 2 * r)) {
    const Real oil = p.z() > Real(0.3) ? 1 : 0;
    fluid.add(p + Vec3(jitter(rng), jitter(rng), jitter(rng)), Vec3::Zero(), volume,
              mix_phases(oil, 1000, Real(0.001), 940, Real(0.004)));
  }
  BoundaryParticles boundary;
  const Aabb domain{Vec3::Constant(-h), Vec3::Constant(Real(0.6) + h)};
  ParticleNeighbourhood nb(domain, kernel, h, boundary);
  nb.update(fluid, boundary);
  SurfaceTensionConfig config;
  config.surface_only = false;
  SurfaceTensionForce force(config, 2 * r, h, 1000);
  force.add_acceleration(fluid, boundary, nb, Real(0.001));
  const std::vector<Vec3d> expected = with_kernel(kernel, h, [&](const auto& w) {
    return direct_surface_tension(
        fluid, w, double(h),
        pair_strengths(config, tension_per_strength(kernel, h, 2 * r, volume, 1000)), 1000);
  });
  double largest = 0, worst = 0;
  Vec3d momentum = Vec3d::Zero();
  for (Index i = 0; i < fluid.size(); ++i) largest = std::max(largest, expected[i].norm());
  for (Index i = 0; i < fluid.size(); ++i) {
    worst = std::max(worst, (fluid.acceleration[i].cast<double>() - expected[i]).norm());
    momentum +=
        double(fluid.rest_density[i] * fluid.rest_volume[i]) * fluid.acceleration[i].cast<double>();
  }
  ASSERT_GT(largest, 0);
  std::cout << "largest deviation from the law " << worst / largest << " of the largest |a| ("
            << largest << " m/s^2)\n";
  // Linear interpolation over (r/h)^2 in 1,024 intervals: within 0.1 % where particles meet.
  EXPECT_LT(worst, 1e-3 * largest) << "largest |a| " << largest << " m/s^2";
  // F_ij = -F_ji also from the table: the total force vanishes.
  EXPECT_LT(momentum.norm(), 1e-4 * largest * double(fluid.size()) * 1000 * double(volume));
}

// The strengths come from physical tensions through lambda, the tension per unit strength of a
// lattice: a force per volume pair summed over an area, so lambda = c rho d^2 at a fixed support
// of two spacings, and s = sigma / lambda grows as 1 / d^2: halving the particles' size keeps
// the tension in N/m. The default crude (S = +0.017 N/m) has s_oil_water > s_oil (it spreads);
// an oil with oil/water tension 0.1 N/m (S < 0) has s_oil_water < s_oil.
TEST(Forces, SurfaceTensionStrengthsFollowTheTensionsAtAnyResolution) {
  for (KernelKind kernel : {KernelKind::kCubicSpline, KernelKind::kWendlandC2}) {
    auto lambda = [&](double d) {
      const Real h = Real(2 * d), volume = lattice_rest_volume(kernel, h, Real(d));
      return double(tension_per_strength(kernel, h, Real(d), volume, 1000));
    };
    const double coarse = lambda(0.04), fine = lambda(0.02);
    std::cout << "lambda at d = 0.04 m: " << coarse << " N/m per m/s^2\n";
    EXPECT_GT(coarse, 0);
    EXPECT_NEAR(coarse / fine, 4.0, 4e-3);
    // The same tension at both sizes: s grows 4x when the particles halve.
    SurfaceTensionConfig crude;
    EXPECT_NEAR(pair_strengths(crude, Real(fine)).water / pair_strengths(crude, Real(coarse)).water,
                4.0, 4e-3);
    const PairStrengths s = pair_strengths(crude, Real(coarse));
    EXPECT_GT(s.oil_water, s.oil);
    // Back to the tensions: sigma_ow = lambda (s_w + s_o - 2 s_ow).
    EXPECT_NEAR(coarse * (s.water + s.oil - 2 * s.oil_water), crude.oil_water, 1e-6);
    SurfaceTensionConfig lens = crude;
    lens.oil_water = Real(0.1);
    const PairStrengths l = pair_strengths(lens, Real(coarse));
    EXPECT_LT(l.oil_water, l.oil);
  }
}

TEST(Forces, SurfaceTensionMatchesTheCosineLawWithTheCubicSpline) {
  expect_surface_tension_matches_the_cosine_law(KernelKind::kCubicSpline);
}

TEST(Forces, SurfaceTensionMatchesTheCosineLawWithWendland) {
  expect_surface_tension_matches_the_cosine_law(KernelKind::kWendlandC2);
}

}  // namespace
}  // namespace sph
