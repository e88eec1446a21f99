// Kernels: normalisation (integral over space = 1, by quadrature) and gradient against central
// finite differences.

#include "sph/core/kernels.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace sph {
namespace {

// 4 pi int_0^h r^2 W(r) dr by composite Simpson with 2000 intervals, in double.
template <class K>
double radial_integral(const K& w) {
  const int n = 2000;
  const double h = w.support_radius(), step = h / n;
  double sum = 0;
  for (int k = 0; k <= n; ++k) {
    const double r = k * step;
    const double f = r * r * double(w.value(Real(r)));
    sum += f * ((k == 0 || k == n) ? 1 : (k % 2 ? 4 : 2));
  }
  return 4 * M_PI * sum * step / 3;
}

template <class K>
void expect_gradient_matches_finite_differences(const K& w) {
  std::mt19937 rng(7);
  const Real h = w.support_radius();
  std::uniform_real_distribution<Real> u(-h, h);
  int checked = 0;
  for (int trial = 0; trial < 500; ++trial) {
    const Vec3 r(u(rng), u(rng), u(rng));
    const Real len = r.norm();
    // Skip points near the origin, the support edge and the cubic spline's knot at h/2, where a
    // finite difference straddles a kink of the second derivative.
    if (len < Real(0.05) * h || len > Real(0.95) * h ||
        std::abs(len - Real(0.5) * h) < Real(0.02) * h)
      continue;
    const Vec3 g = w.gradient(r);
    const double step = 1e-3 * double(h);
    for (int k = 0; k < 3; ++k) {
      Vec3 a = r, b = r;
      a[k] += Real(step);
      b[k] -= Real(step);
      const double fd = (double(w.value(a)) - double(w.value(b))) / (2 * step);
      // Tolerance: 0.5 % of the kernel's gradient scale W(0)/h (float rounding dominates).
      EXPECT_NEAR(double(g[k]), fd, 5e-3 * double(w.value(Real(0))) / double(h))
          << "component " << k << " at r = " << r.transpose();
    }
    ++checked;
  }
  EXPECT_GT(checked, 200);
}

TEST(Kernels, CubicSplineIntegratesToOne) {
  for (Real h : {Real(0.1), Real(1.0), Real(0.02)})
    EXPECT_NEAR(radial_integral(CubicSplineKernel(h)), 1.0, 1e-5) << "h = " << h;
}

TEST(Kernels, WendlandC2IntegratesToOne) {
  for (Real h : {Real(0.1), Real(1.0), Real(0.02)})
    EXPECT_NEAR(radial_integral(WendlandC2Kernel(h)), 1.0, 1e-5) << "h = " << h;
}

TEST(Kernels, CubicSplineGradientMatchesFiniteDifferences) {
  expect_gradient_matches_finite_differences(CubicSplineKernel(Real(0.1)));
}

TEST(Kernels, WendlandC2GradientMatchesFiniteDifferences) {
  expect_gradient_matches_finite_differences(WendlandC2Kernel(Real(0.1)));
}

TEST(Kernels, VanishAtSupportAndAreContinuousAtKnot) {
  const CubicSplineKernel c(1);
  const WendlandC2Kernel w(1);
  EXPECT_EQ(c.value(Real(1)), 0);
  EXPECT_EQ(w.value(Real(1)), 0);
  EXPECT_EQ(c.gradient(Vec3(1, 0, 0)).norm(), 0);
  EXPECT_NEAR(c.value(Real(0.5) - Real(1e-6)), c.value(Real(0.5) + Real(1e-6)), 1e-5);
  EXPECT_EQ(c.gradient(Vec3::Zero()).norm(), 0);  // no NaN at r = 0
}

TEST(Kernels, GradientsOfASymmetricLatticeSumToZero) {
  const CubicSplineKernel w(Real(0.1));
  Vec3 sum = Vec3::Zero();
  double scale = 0;
  for (int i = -3; i <= 3; ++i)
    for (int j = -3; j <= 3; ++j)
      for (int k = -3; k <= 3; ++k) {
        const Vec3 g = w.gradient(Vec3(Real(i), Real(j), Real(k)) * Real(0.025));
        sum += g;
        scale += double(g.norm());
      }
  EXPECT_LT(double(sum.norm()), 1e-6 * scale);
}

}  // namespace
}  // namespace sph
