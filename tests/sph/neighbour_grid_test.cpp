// Neighbour search against brute force, including points exactly on cell borders.

#include "sph/core/neighbour_grid.h"
#include "sph/core/neighbour_row_scan.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace sph {
namespace {

std::vector<std::vector<Index>> brute_force(const std::vector<Vec3>& queries,
                                            const std::vector<Vec3>& points, Real radius,
                                            bool same_set) {
  std::vector<std::vector<Index>> out(queries.size());
  for (size_t i = 0; i < queries.size(); ++i)
    for (size_t j = 0; j < points.size(); ++j)
      if ((!same_set || i != j) && (queries[i] - points[j]).squaredNorm() < radius * radius)
        out[i].push_back(Index(j));
  return out;
}

std::vector<Vec3> test_points(Real radius, const Aabb& box, int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<Real> ux(box.min[0], box.max[0]), uy(box.min[1], box.max[1]),
      uz(box.min[2], box.max[2]);
  std::uniform_int_distribution<int> cell(0, 5);
  std::vector<Vec3> points;
  for (int k = 0; k < count; ++k) {
    Vec3 p(ux(rng), uy(rng), uz(rng));
    // A third of the points sit exactly on cell borders in one or more coordinates.
    if (k % 3 == 0) p[k % 2] = box.min[k % 2] + Real(cell(rng)) * radius;
    if (k % 9 == 0) p = box.min + Vec3::Constant(Real(cell(rng)) * radius);
    p = p.cwiseMin(box.max);
    points.push_back(p);
  }
  return points;
}

void expect_equal_to_brute_force(const NeighbourLists& lists,
                                 const std::vector<std::vector<Index>>& expected) {
  ASSERT_EQ(lists.queries(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    std::vector<Index> got(lists.indices.begin() + lists.offsets[i],
                           lists.indices.begin() + lists.offsets[i + 1]);
    std::sort(got.begin(), got.end());
    ASSERT_EQ(got, expected[i]) << "query " << i;
  }
}

TEST(NeighbourGrid, SameSetEqualsBruteForce) {
  const Real radius = Real(0.1);
  const Aabb box{Vec3(-0.3f, 0, 0.1f), Vec3(0.3f, 0.5f, 0.5f)};
  const auto points = test_points(radius, box, 3000, 1);
  NeighbourGrid grid(box, radius);
  grid.build(points);
  NeighbourLists lists;
  grid.find(points.data(), Index(points.size()), true, lists);
  expect_equal_to_brute_force(lists, brute_force(points, points, radius, true));
  size_t total = 0;
  for (Index i = 0; i < lists.queries(); ++i) total += lists.count(i);
  EXPECT_GT(total, points.size() * 10);  // the test exercises real neighbourhoods
}

TEST(NeighbourGrid, OtherSetEqualsBruteForce) {
  const Real radius = Real(0.07);
  const Aabb box{Vec3(0, 0, 0), Vec3(0.42f, 0.35f, 0.28f)};
  const auto points = test_points(radius, box, 2000, 2);
  const auto queries = test_points(radius, box, 500, 3);
  NeighbourGrid grid(box, radius);
  grid.build(points);
  NeighbourLists lists;
  grid.find(queries.data(), Index(queries.size()), false, lists);
  expect_equal_to_brute_force(lists, brute_force(queries, points, radius, false));
}

TEST(NeighbourGrid, ForEachNearEqualsBruteForce) {
  const Real radius = Real(0.1);
  const Aabb box{Vec3(0, 0, 0), Vec3(0.5f, 0.5f, 0.5f)};
  const auto points = test_points(radius, box, 1000, 4);
  NeighbourGrid grid(box, radius);
  grid.build(points);
  const auto expected = brute_force(points, points, radius, false);
  for (size_t i = 0; i < points.size(); i += 7) {
    std::vector<Index> got;
    grid.for_each_near(points[i], [&](Index j) { got.push_back(j); });
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, expected[i]);
  }
}

TEST(NeighbourGrid, CellOrderIsAPermutation) {
  const Aabb box{Vec3(0, 0, 0), Vec3(1, 1, 1)};
  const auto points = test_points(Real(0.1), box, 777, 5);
  NeighbourGrid grid(box, Real(0.1));
  grid.build(points);
  std::vector<Index> order = grid.cell_order();
  std::sort(order.begin(), order.end());
  for (size_t k = 0; k < order.size(); ++k) ASSERT_EQ(order[k], k);
}

TEST(NeighbourGrid, PointOutsideOrNaNIsReportedWithItsIndex) {
  const Aabb box{Vec3(0, 0, 0), Vec3(1, 1, 1)};
  NeighbourGrid grid(box, Real(0.1));
  std::vector<Vec3> points = {Vec3(0.5f, 0.5f, 0.5f), Vec3(0.5f, 1.5f, 0.5f)};
  try {
    grid.build(points);
    FAIL() << "expected PointOutsideDomain";
  } catch (const PointOutsideDomain& e) {
    EXPECT_EQ(e.index(), 1u);
  }
  points[1] = Vec3(std::nanf(""), 0.5f, 0.5f);
  EXPECT_THROW(grid.build(points), PointOutsideDomain);
}

// Every SIMD version of the innermost scan returns exactly the scalar one's list, in the same
// order, for ranges of every length (whole vectors and every tail) and for points placed on the
// radius to within a rounding step, where a differently rounded distance would flip the answer.
TEST(NeighbourRowScan, EveryVersionReturnsTheScalarList) {
  const std::vector<RowScanVersion> versions = available_row_scans();
  ASSERT_EQ(versions.front().name, "scalar");
  std::mt19937 rng(11);
  std::uniform_real_distribution<Real> unit(-1, 1);
  const Real radius = Real(0.05), r2 = radius * radius;
  const int count = 4000;
  std::vector<Real> x(count), y(count), z(count);
  std::vector<Index> index(count);
  const Real q[3] = {Real(0.3), Real(-0.2), Real(0.1)};
  for (int k = 0; k < count; ++k) {
    Vec3 d(unit(rng), unit(rng), unit(rng));
    d.normalize();
    // A third just inside, on or just outside the radius, the rest anywhere within 1.5 radii.
    const Real scale = k % 3 == 0 ? radius * (Real(1) + Real(2e-7) * Real(k % 5 - 2))
                                  : Real(1.5) * radius * std::abs(unit(rng));
    x[k] = q[0] + scale * d[0];
    y[k] = q[1] + scale * d[1];
    z[k] = q[2] + scale * d[2];
    index[k] = Index(count - k);  // not the slot: the scans must return the caller's index
  }
  const SortedPoints points{x.data(), y.data(), z.data(), index.data()};
  std::vector<Index> expected(count + kRowScanSlack), got(count + kRowScanSlack);
  size_t borderline = 0;
  for (int k = 0; k < count; ++k) {
    const Real dx = x[k] - q[0], dy = y[k] - q[1], dz = z[k] - q[2];
    borderline += std::abs(dx * dx + dy * dy + dz * dz - r2) < Real(1e-6) * r2;
  }
  EXPECT_GT(borderline, size_t(count / 10));  // the test really probes the radius
  for (const RowScanVersion& version : versions) {
    SCOPED_TRACE(version.name);
    for (Index begin = 0; begin < 40; begin += 3)
      for (Index length = 0; length <= 70; ++length) {
        for (const Index self : {~Index(0), index[begin + length / 2]}) {
          const size_t want =
              versions.front().scan(points, begin, begin + length, q, r2, self, expected.data());
          const size_t have = version.scan(points, begin, begin + length, q, r2, self, got.data());
          ASSERT_EQ(have, want) << "range " << begin << " + " << length;
          for (size_t t = 0; t < want; ++t) ASSERT_EQ(got[t], expected[t]) << "entry " << t;
        }
      }
    // One long range, as a dense cell row gives.
    const size_t want =
        versions.front().scan(points, 0, Index(count), q, r2, ~Index(0), expected.data());
    ASSERT_EQ(version.scan(points, 0, Index(count), q, r2, ~Index(0), got.data()), want);
    for (size_t t = 0; t < want; ++t) ASSERT_EQ(got[t], expected[t]);
  }
}

// The grid's search equals brute force with whichever scan it uses.
TEST(NeighbourRowScan, TheGridEqualsBruteForceWithEveryVersion) {
  const Real radius = Real(0.1);
  const Aabb box{Vec3(-0.3f, 0, 0.1f), Vec3(0.3f, 0.5f, 0.5f)};
  const auto points = test_points(radius, box, 3000, 7);
  const auto expected = brute_force(points, points, radius, true);
  for (const RowScanVersion& version : available_row_scans()) {
    SCOPED_TRACE(version.name);
    NeighbourGrid grid(box, radius);
    grid.use_row_scan(version.scan);
    grid.build(points);
    NeighbourLists lists;
    grid.find(points.data(), Index(points.size()), true, lists);
    expect_equal_to_brute_force(lists, expected);
  }
}

}  // namespace
}  // namespace sph
