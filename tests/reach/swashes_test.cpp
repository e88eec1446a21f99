// The reach's shallow-water solver against analytic solutions from the SWASHES catalogue
// (Delestre, Lucas, Ksinant, Darboux, Laguerre, Vo, James & Cordier, "SWASHES: a compilation of
// shallow water analytic solutions for hydraulic and environmental studies", Int. J. Numer. Meth.
// Fluids 72, 2013): each case with its error norm and bound, and the order of convergence on two
// grids where the solution has a place to converge to.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <iostream>
#include <string>

#include "reach/raster.h"
#include "reach/shallow_water.h"

namespace {

constexpr double kG = 9.81;

// A channel of length L along x, one cell across, walls at both ends.
reach::ShallowWaterSolver channel(int cells, double length,
                                  const std::function<double(double)>& bed, double manning = 0.0) {
  reach::Grid g;
  g.nx = cells, g.ny = 1, g.dx = length / cells, g.dy = length / cells;
  reach::Field z(g.cells());
  for (int i = 0; i < cells; ++i) z[size_t(i)] = bed(g.x(i));
  return reach::ShallowWaterSolver(g, z, {manning});
}

// sum |h - h_exact| dA / sum h_exact dA over the grid.
double relative_l1(const reach::ShallowWaterSolver& s,
                   const std::function<double(double, double)>& exact) {
  const reach::Grid& g = s.grid();
  double error = 0, norm = 0;
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      const double e = exact(g.x(i), g.y(j));
      error += std::abs(s.state().h[g.at(i, j)] - e);
      norm += e;
    }
  return error / norm;
}

double order(double coarse_error, double fine_error) {
  return std::log(coarse_error / fine_error) / std::log(2.0);
}

// The figures behind a test's bounds, on the test's output for the record.
void report(const std::string& name, const double errors[2]) {
  std::cout << name << ": relative L1 depth error " << errors[0] << " (coarse), " << errors[1]
            << " (fine), order " << order(errors[0], errors[1]) << "\n";
}

// The furthest x downstream where the depth exceeds `threshold`.
double front(const reach::ShallowWaterSolver& s, double threshold) {
  const reach::Grid& g = s.grid();
  double x = g.x(0);
  for (int i = 0; i < g.nx; ++i)
    if (s.state().h[g.at(i, 0)] > threshold) x = g.x(i) + 0.5 * g.dx;
  return x;
}

}  // namespace

// SWASHES 3.1.2: a lake at rest with an emerged bump. Water at 0.1 m over
// z = 0.2 - 0.05 (x - 10)^2 on 8 < x < 12 (top at 0.2 m, dry), 25 m long: the scheme keeps it
// at rest to round-off.
TEST(Swashes, LakeAtRestOverAnEmergedBumpStaysAtRest) {
  auto s = channel(200, 25.0, [](double x) {
    return (x > 8 && x < 12) ? 0.2 - 0.05 * (x - 10) * (x - 10) : 0.0;
  });
  s.fill_to_level(0.1);
  const double volume = s.volume();
  s.advance_to(100.0);
  double fastest = 0, level_error = 0;
  for (size_t c = 0; c < s.grid().cells(); ++c) {
    fastest = std::max(fastest, std::abs(s.state().hu[c]));
    if (s.state().h[c] > 0)
      level_error = std::max(level_error, std::abs(s.state().h[c] + s.bed()[c] - 0.1));
  }
  std::cout << "lake at rest, emerged bump: largest |hu| " << fastest << " m^2/s, level error "
            << level_error << " m\n";
  EXPECT_LT(fastest, 1e-12);  // unit discharge, m^2/s
  EXPECT_LT(level_error, 1e-12);
  EXPECT_NEAR(s.volume(), volume, 1e-12 * volume);
}

// The same over a rough 2D bed with islands, closed cells and a wall: velocities at round-off.
TEST(Swashes, LakeAtRestOverARoughBedWithIslandsStaysAtRest) {
  reach::Grid g;
  g.nx = 48, g.ny = 32, g.dx = 2.0, g.dy = 2.0;
  reach::Field z(g.cells());
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i)
      z[g.at(i, j)] =
          0.6 * std::sin(0.37 * i) * std::cos(0.51 * j) + 0.3 * std::sin(1.7 * i + 2.3 * j);
  z[g.at(10, 10)] = std::nan("");  // a closed cell inside the water
  reach::ShallowWaterSolver s(g, z, {0.03});
  s.fill_to_level(0.2);
  s.advance_to(200.0);
  double fastest = 0;
  for (size_t c = 0; c < g.cells(); ++c)
    if (s.state().h[c] > 0)
      fastest = std::max(fastest, std::hypot(s.state().hu[c], s.state().hv[c]) / s.state().h[c]);
  std::cout << "lake at rest, rough bed: largest speed " << fastest << " m/s\n";
  EXPECT_LT(fastest, 1e-10);  // m/s
}

// The lake at rest on real terrain: the Waikanae DEM (terrain/waikanae_river_10m) filled to
// 6 m, its river and hollows wet among emerged dunes and terraces, for 10 minutes.
TEST(Swashes, LakeAtRestOnTheWaikanaeDemStaysAtRest) {
  const reach::Raster dem = reach::read_raster(std::string(SPILL_SOURCE_DIR) +
                                               "/terrain/waikanae_river_10m/waikanae_dem_10m.tif");
  reach::ShallowWaterSolver s(dem.grid, dem.values, {0.035});
  s.fill_to_level(6.0);
  long wet = 0;
  for (double h : s.state().h) wet += h > 0;
  ASSERT_GT(wet, 500);
  ASSERT_LT(wet, long(dem.grid.cells()) - 500);
  s.advance_to(600.0);
  double fastest = 0;
  for (size_t c = 0; c < dem.grid.cells(); ++c)
    if (s.state().h[c] > 0)
      fastest = std::max(fastest, std::hypot(s.state().hu[c], s.state().hv[c]) / s.state().h[c]);
  std::cout << "lake at rest, Waikanae DEM: largest speed " << fastest << " m/s\n";
  EXPECT_LT(fastest, 1e-10);  // m/s
}

// SWASHES 4.1.2: Ritter's dam break on a dry bed, h_l = 5 mm at x < 5 m, t = 6 s.
TEST(Swashes, RittersDamBreakOnADryBed) {
  const double hl = 0.005, x0 = 5.0, t = 6.0, c = std::sqrt(kG * hl);
  const auto exact = [&](double x, double) {
    if (x <= x0 - t * c) return hl;
    if (x >= x0 + 2 * t * c) return 0.0;
    const double r = c - (x - x0) / (2 * t);
    return 4.0 / (9.0 * kG) * r * r;
  };
  double errors[2], lag_5[2], lag_1[2];
  for (int k = 0; k < 2; ++k) {
    auto s = channel(200 << k, 10.0, [](double) { return 0.0; });
    for (int i = 0; i < s.grid().nx; ++i) s.state().h[size_t(i)] = s.grid().x(i) < x0 ? hl : 0.0;
    s.advance_to(t);
    errors[k] = relative_l1(s, exact);
    // The wet front against Ritter's: where the depth exceeds 5 % of h_l, and where it
    // exceeds 1 %, near the tip where the exact depth vanishes quadratically and a grid's thin
    // film lags most.
    const auto lag = [&](double share) {
      return x0 + 2 * t * (c - 1.5 * std::sqrt(share * kG * hl)) - front(s, share * hl);
    };
    lag_5[k] = lag(0.05);
    lag_1[k] = lag(0.01);
  }
  // Within 2 % of the distance the front travelled at 5 %; at 1 % the lag shrinks at first
  // order with the grid.
  EXPECT_LT(std::abs(lag_5[1]), 0.02 * 2 * t * c) << lag_5[1];
  EXPECT_GT(lag_1[0], 0);
  EXPECT_LT(lag_1[1], 0.6 * lag_1[0]) << lag_1[0] << " " << lag_1[1];
  report("Ritter", errors);
  EXPECT_LT(errors[1], 0.01);
  EXPECT_GT(order(errors[0], errors[1]), 0.7);
}

// SWASHES 4.1.1: Stoker's dam break on a wet bed, h_l = 5 mm, h_r = 1 mm, t = 6 s: a
// rarefaction, a constant state and a bore.
TEST(Swashes, StokersDamBreakOnAWetBed) {
  const double hl = 0.005, hr = 0.001, x0 = 5.0, t = 6.0;
  const double cl = std::sqrt(kG * hl);
  // c_m = sqrt(g h_m) of the middle state: the root in (sqrt(g h_r), sqrt(g h_l)) of
  // -8 g h_r c^2 (sqrt(g h_l) - c)^2 + (c^2 - g h_r)^2 (c^2 + g h_r) = 0, where the
  // rarefaction's u_m = 2 (sqrt(g h_l) - c_m) meets the bore's jump conditions.
  const auto f = [&](double c) {
    const double c2 = c * c;
    return -8 * kG * hr * c2 * (cl - c) * (cl - c) +
           (c2 - kG * hr) * (c2 - kG * hr) * (c2 + kG * hr);
  };
  double lo = std::sqrt(kG * hr), hi = cl;
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    ((f(lo) < 0) == (f(mid) < 0) ? lo : hi) = mid;
  }
  const double cm = 0.5 * (lo + hi);
  const double xa = x0 - t * cl, xb = x0 + t * (2 * cl - 3 * cm);
  const double xc = x0 + t * 2 * cm * cm * (cl - cm) / (cm * cm - kG * hr);
  const auto exact = [&](double x, double) {
    if (x <= xa) return hl;
    if (x <= xb) {
      const double r = cl - (x - x0) / (2 * t);
      return 4.0 / (9.0 * kG) * r * r;
    }
    if (x <= xc) return cm * cm / kG;
    return hr;
  };
  double errors[2];
  for (int k = 0; k < 2; ++k) {
    auto s = channel(200 << k, 10.0, [](double) { return 0.0; });
    for (int i = 0; i < s.grid().nx; ++i) s.state().h[size_t(i)] = s.grid().x(i) < x0 ? hl : hr;
    s.advance_to(t);
    errors[k] = relative_l1(s, exact);
    if (k == 1) {
      // The bore: where the depth crosses halfway between the middle state and h_r.
      const double half = 0.5 * (cm * cm / kG + hr);
      EXPECT_NEAR(front(s, half), xc, 2 * s.grid().dx);
    }
  }
  report("Stoker", errors);
  EXPECT_LT(errors[1], 0.01);
  EXPECT_GT(order(errors[0], errors[1]), 0.7);
}

// SWASHES 4.2.2: Thacker's planar surface in a paraboloid, a = 1 m, h_0 = 0.1 m, eta = 0.5,
// on [0, 4]^2: the water sheet rotates with period 2 pi / omega, omega = sqrt(2 g h_0) / a, and
// its shoreline moves over the dry bowl. One period on two grids; the volume conserved to
// round-off (no water reaches the walls).
TEST(Swashes, ThackersPlanarSurfaceInAParaboloid) {
  const double a = 1.0, h0 = 0.1, eta = 0.5, L = 4.0;
  const double omega = std::sqrt(2 * kG * h0) / a, period = 2 * M_PI / omega;
  const auto bed = [&](double x, double y) {
    const double r2 = (x - L / 2) * (x - L / 2) + (y - L / 2) * (y - L / 2);
    return -h0 * (1 - r2 / (a * a));
  };
  const auto exact_at = [&](double t) {
    return [&, t](double x, double y) {
      const double level =
          eta * h0 / (a * a) *
          (2 * (x - L / 2) * std::cos(omega * t) + 2 * (y - L / 2) * std::sin(omega * t) - eta);
      return std::max(0.0, level - bed(x, y));
    };
  };
  double errors[2];
  for (int k = 0; k < 2; ++k) {
    reach::Grid g;
    g.nx = g.ny = 50 << k;
    g.dx = g.dy = L / g.nx;
    reach::Field z(g.cells());
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i) z[g.at(i, j)] = bed(g.x(i), g.y(j));
    reach::ShallowWaterSolver s(g, z, {0.0});
    const auto start = exact_at(0.0);
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i) {
        const size_t c = g.at(i, j);
        s.state().h[c] = start(g.x(i), g.y(j));
        s.state().hv[c] =
            s.state().h[c] * eta * omega;  // u = -eta omega sin 0, v = eta omega cos 0
      }
    const double volume = s.volume();
    s.advance_to(period);
    errors[k] = relative_l1(s, exact_at(period));
    EXPECT_NEAR(s.volume() - s.clamped_volume(), volume, 1e-12 * volume);
    EXPECT_LT(s.clamped_volume(), 1e-6 * volume);
  }
  report("Thacker", errors);
  EXPECT_LT(errors[1], 0.05);
  EXPECT_GT(order(errors[0], errors[1]), 0.7);
}

// Uniform flow in a tilted channel: a discharge of q = 1 m^2/s on a slope of 1e-3 with
// Manning's n = 0.03 settles at the normal depth (n q / sqrt(S))^(3/5) = 0.969 m, entering dry
// and leaving through a normal-depth outflow; the outflow then carries the inflow.
TEST(Swashes, UniformFlowSettlesAtTheNormalDepth) {
  const double slope = 1e-3, n = 0.03, width = 20.0, q = 1.0;
  reach::Grid g;
  g.nx = 60, g.ny = 4, g.dx = g.dy = 5.0;
  reach::Field z(g.cells());
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) z[g.at(i, j)] = -slope * g.x(i);
  reach::ShallowWaterSolver s(g, z, {n});
  s.add_inflow({{reach::Side::kWest, 0, g.ny - 1}, reach::Hydrograph(q * width), "upstream", {}});
  reach::OutflowBoundary out;
  out.section = {reach::Side::kEast, 0, g.ny - 1};
  out.kind = reach::OutflowKind::kNormalDepth;
  out.slope = slope;
  s.add_outflow(out);
  s.advance_to(4000.0);
  const double normal_depth = std::pow(n * q / std::sqrt(slope), 0.6);
  double worst = 0;
  for (int i = g.nx / 3; i < 2 * g.nx / 3; ++i)
    for (int j = 0; j < g.ny; ++j)
      worst = std::max(worst, std::abs(s.state().h[g.at(i, j)] / normal_depth - 1));
  std::cout << "uniform flow: depth within " << worst << " of the normal depth, outflow "
            << -s.section_discharge()[1] << " of " << q * width << " m^3/s\n";
  for (int i = g.nx / 3; i < 2 * g.nx / 3; ++i)
    for (int j = 0; j < g.ny; ++j)
      EXPECT_NEAR(s.state().h[g.at(i, j)], normal_depth, 0.01 * normal_depth) << i << "," << j;
  ASSERT_EQ(s.section_discharge().size(), 2u);
  EXPECT_NEAR(s.section_discharge()[0], q * width, 1e-9 * q * width);
  EXPECT_NEAR(-s.section_discharge()[1], q * width, 0.005 * q * width);
  // The volume balance: what is in the reach is what came in less what left.
  EXPECT_NEAR(s.volume(), s.boundary_volume_in() + s.clamped_volume(), 1e-9 * s.volume());
}
