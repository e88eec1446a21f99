// Boundary sampling and Akinci volumes.

#include "sph/boundary/boundary.h"

#include <gtest/gtest.h>

#include <cmath>

namespace sph {
namespace {

// On an infinite flat wall sampled on a square lattice of spacing s, Akinci's volume
// V_b = 1 / sum_k W(x_b - x_k) tends to s^2 / I with I = int int W(x, y, 0) dx dy (the lattice sum
// of a smooth kernel approximates the integral / s^2). I is computed here by 2D quadrature,
// independently of the sampling code.
double plane_integral_of_kernel(Real h) {
  const CubicSplineKernel w(h);
  const int n = 400;
  const double step = 2.0 * double(h) / n;
  double sum = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double x = -double(h) + (i + 0.5) * step, y = -double(h) + (j + 0.5) * step;
      sum += double(w.value(Real(std::sqrt(x * x + y * y))));
    }
  return sum * step * step;
}

TEST(Boundary, FlatWallVolumesMatchTheKernelPlaneIntegral) {
  const Real r = Real(0.025), h = 4 * r, spacing = 2 * r;
  // A 1 m x 1 m plate (one face of a thin box would add the other faces; sample a plate).
  std::vector<Vec3> plate;
  for (int i = 0; i <= 20; ++i)
    for (int j = 0; j <= 20; ++j) plate.emplace_back(Real(i) * spacing, Real(j) * spacing, 0);
  const auto volume = boundary_volumes(plate, KernelKind::kCubicSpline, h);
  const double expected = double(spacing * spacing) / plane_integral_of_kernel(h);
  int interior = 0;
  for (size_t k = 0; k < plate.size(); ++k) {
    const Vec3& p = plate[k];
    const bool inside = p[0] > 2 * h && p[0] < 1 - 2 * h && p[1] > 2 * h && p[1] < 1 - 2 * h;
    if (!inside) continue;
    ++interior;
    EXPECT_NEAR(double(volume[k]), expected, 0.02 * expected) << "at " << p.transpose();
  }
  EXPECT_GT(interior, 100);
  // At the plate's edge fewer neighbours give larger volumes (the correction Akinci describes).
  EXPECT_GT(double(volume[0]), 1.3 * expected);
}

TEST(Boundary, BoxSurfaceHasNoDuplicatesAndEvenSpacing) {
  const Real spacing = Real(0.05);
  const auto points = sample_box_surface(Vec3(0, 0, 0), Vec3(1, 0.5f, 0.3f), spacing, false);
  // Faces: 21x11 (z faces), 21x7 (y faces), 11x7 (x faces), shared edges/corners once.
  const size_t lattice = 2 * 21 * 11 + 2 * 21 * 5 + 2 * 9 * 5;
  EXPECT_EQ(points.size(), lattice);
  for (size_t a = 0; a < points.size(); ++a)
    for (size_t b = a + 1; b < points.size(); ++b)
      ASSERT_GT((points[a] - points[b]).norm(), Real(0.9) * spacing);
  const auto open = sample_box_surface(Vec3(0, 0, 0), Vec3(1, 0.5f, 0.3f), spacing, true);
  EXPECT_EQ(open.size(), lattice - 19 * 9);  // the top face's interior nodes are gone
}

TEST(Boundary, HeightFieldFollowsTheSurfaceAndFillsSteps) {
  HeightFieldConfig field;
  field.origin = Vec3(0, 0, 0);
  field.cell_size = 1;
  field.heights = {{0, 0, 0.5f}, {0, 0, 0.5f}};  // a 0.5 m step between x = 1 and x = 2
  const Real spacing = Real(0.1);
  const auto points = sample_height_field(field, spacing);
  for (const auto& p : points) {
    const Real surface = p[0] <= 1 ? 0 : Real(0.5) * (p[0] - 1);
    EXPECT_LE(p[2], surface + Real(1e-5));
  }
  // Along the slope (rise 0.05 per 0.1 step) no filling is needed; every column is one point.
  EXPECT_EQ(points.size(), size_t(21 * 11));
  // A 0.8 m cliff over one 0.1 m cell: the high column is filled down to the low side's level
  // (8 extra points per column), so two rows of columns hold 2 * (1 + 1 + 8) points.
  field.heights = {{0, 0.8f}, {0, 0.8f}};
  field.cell_size = Real(0.1);
  EXPECT_EQ(sample_height_field(field, spacing).size(), size_t(20));
}

}  // namespace
}  // namespace sph
