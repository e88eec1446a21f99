// Non-pressure forces on a small lattice with random velocities: viscosity and XSPH exchange
// momentum between pairs symmetrically (total momentum is conserved) and smooth the velocity
// field (its variance falls); gravity adds g to every particle.

#include <gtest/gtest.h>

#include <random>

#include "sph/gravity_force.h"
#include "sph/lattice.h"
#include "sph/viscosity_force.h"
#include "sph/xsph_force.h"

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

}  // namespace
}  // namespace sph
