// The pressure terms shared by DFSPH, IISPH and PBF (sph/solvers/pressure_terms.h).

#include "sph/solvers/pressure_terms.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "sph/boundary/boundary.h"
#include "sph/neighbours/neighbourhood.h"

namespace sph {
namespace {

// PBF moves its constraints between iterations by density_change (the first-order change of
// rho_i under a displacement) instead of re-evaluating the kernels: on a jittered block of fluid
// resting on a boundary floor, displaced by up to 1e-3 d per axis (PBF's corrections), it must
// give the re-evaluated densities to 1e-5 (the neglected second-order terms are ~(dx/h)^2 ~ 1e-6
// times the kernel's curvature sums; float rounding of a sum of ~50 terms is ~1e-6), and do at
// least 20x better than assuming no change at all (so the displacement matters).
TEST(PressureTerms, DensityChangeIsTheFirstOrderChangeOfTheDensity) {
  const Real d = Real(0.02), h = 2 * d;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> jitter(-0.05f, 0.05f), move(-1e-3f, 1e-3f);
  FluidParticles fluid;
  PhaseMix water;
  for (int x = 0; x < 8; ++x)
    for (int y = 0; y < 8; ++y)
      for (int z = 0; z < 6; ++z) {
        const Vec3 p = d * Vec3(Real(x) + jitter(rng), Real(y) + jitter(rng),
                                Real(z) + Real(0.5) + jitter(rng));
        fluid.add(p, Vec3::Zero(), d * d * d, water);
      }
  BoundaryParticles floor;
  for (int x = -3; x < 11; ++x)
    for (int y = -3; y < 11; ++y) floor.position.push_back(Vec3(Real(x) * d, Real(y) * d, 0));
  floor.volume = boundary_volumes(floor.position, KernelKind::kCubicSpline, h);
  Aabb domain;
  domain.min = Vec3::Constant(-0.2f);
  domain.max = Vec3::Constant(0.4f);
  ParticleNeighbourhood nb(domain, KernelKind::kCubicSpline, h, floor);
  nb.update(fluid, floor);

  const Index n = fluid.active_count();
  std::vector<Vec3> dx(static_cast<size_t>(n));
  for (auto& v : dx) v = d * Vec3(move(rng), move(rng), move(rng));
  std::vector<double> before(static_cast<size_t>(n)), predicted(static_cast<size_t>(n));
  for (Index i = 0; i < n; ++i) {
    before[i] = double(fluid.density[i]);
    predicted[i] = before[i] + double(pressure_terms::density_change(i, nb, dx));
  }
  for (Index i = 0; i < n; ++i) fluid.position[i] += dx[i];
  nb.update_pair_kernels(fluid, floor);

  double first_order_error = 0, no_change_error = 0;
  for (Index i = 0; i < n; ++i) {
    first_order_error = std::max(first_order_error, std::abs(predicted[i] - fluid.density[i]));
    no_change_error = std::max(no_change_error, std::abs(before[i] - fluid.density[i]));
  }
  std::cout << "largest error: first order " << first_order_error << ", no change "
            << no_change_error << "\n";
  EXPECT_LT(first_order_error, 1e-5);
  EXPECT_GT(no_change_error, 20 * first_order_error);
}

}  // namespace
}  // namespace sph
