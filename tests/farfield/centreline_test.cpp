// Centreline::locate against the definition it implements: the nearest point of the polyline
// (its end segments extended beyond the line's ends), found here by measuring every segment.
// locate measures only the candidates of a grid cell; on a meandering line of uneven segments,
// at random points inside, near and far outside its grid, and on its vertices, it must give the
// same place along the line and the same offset, to 1e-9 m.

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "farfield/model/centreline.h"

namespace {

using Points = std::vector<std::pair<double, double>>;

farfield::RiverPosition measure_every_segment(const Points& p, double x, double y) {
  farfield::RiverPosition best;
  double best_distance = INFINITY, along = 0;
  for (size_t k = 0; k + 1 < p.size(); ++k) {
    const double dx = p[k + 1].first - p[k].first, dy = p[k + 1].second - p[k].second;
    const double len = std::hypot(dx, dy);
    double t = ((x - p[k].first) * dx + (y - p[k].second) * dy) / (len * len);
    if (k > 0) t = std::max(t, 0.0);
    if (k + 2 < p.size()) t = std::min(t, 1.0);
    const double distance = std::hypot(x - p[k].first - t * dx, y - p[k].second - t * dy);
    if (distance < best_distance) {
      best_distance = distance;
      best.along_m = along + t * len;
      const bool left = dx * (y - p[k].second) - dy * (x - p[k].first) >= 0;
      best.offset_m = left ? distance : -distance;
    }
    along += len;
  }
  return best;
}

Points meander() {
  Points p;
  std::mt19937 random(7);
  std::uniform_real_distribution<double> step(5, 120);
  double s = 0;
  for (int k = 0; k < 300; ++k) {
    p.push_back({500000 + s, 4200000 + 400 * std::sin(s / 700) + 150 * std::sin(s / 130)});
    s += step(random);
  }
  return p;
}

}  // namespace

TEST(Centreline, LocateEqualsMeasuringEverySegment) {
  const Points p = meander();
  const farfield::Centreline line(p);
  std::mt19937 random(11);
  const double x0 = p.front().first, x1 = p.back().first;
  std::uniform_real_distribution<double> x(x0 - 0.5 * (x1 - x0), x1 + 0.5 * (x1 - x0));
  std::uniform_real_distribution<double> y(4200000 - 3000, 4200000 + 3000);
  std::uniform_real_distribution<double> near(-60, 60);
  std::vector<std::pair<double, double>> queries;
  for (int k = 0; k < 20000; ++k) queries.push_back({x(random), y(random)});
  for (size_t k = 0; k < p.size(); ++k) {
    queries.push_back(p[k]);
    queries.push_back({p[k].first + near(random), p[k].second + near(random)});
  }
  int far_outside = 0;
  for (const auto& [qx, qy] : queries) {
    const farfield::RiverPosition got = line.locate(qx, qy);
    const farfield::RiverPosition want = measure_every_segment(p, qx, qy);
    ASSERT_NEAR(got.along_m, want.along_m, 1e-9 * std::max(1.0, std::fabs(want.along_m)))
        << "at " << qx << ", " << qy;
    ASSERT_NEAR(std::fabs(got.offset_m), std::fabs(want.offset_m), 1e-9) << qx << ", " << qy;
    if (std::fabs(want.offset_m) > 1e-6) {
      EXPECT_EQ(got.offset_m > 0, want.offset_m > 0);
    }
    far_outside += std::fabs(want.offset_m) > 2500;
  }
  // The queries reach beyond the grid, where every segment is measured.
  EXPECT_GT(far_outside, 100);
}

TEST(Centreline, AStraightLineGivesDistanceAlongAndSignedOffset) {
  const farfield::Centreline line(
      {{0.0, 10.0}, {100.0, 10.0}, {250.0, 10.0}, {400.0, 10.0}, {600.0, 10.0}, {1000.0, 10.0}});
  for (const double x : {-50.0, 0.0, 37.5, 399.0, 999.0, 1300.0})
    for (const double y : {-40.0, 10.0, 12.5, 300.0}) {
      const farfield::RiverPosition r = line.locate(x, y);
      EXPECT_NEAR(r.along_m, x, 1e-9);
      EXPECT_NEAR(r.offset_m, y - 10, 1e-9);  // the left bank of an eastward river is north
    }
}
