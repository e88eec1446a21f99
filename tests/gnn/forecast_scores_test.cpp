// The scores a chaotic flow allows (issue 48, section 3), each against a result derived by hand
// or an independent brute force: the debiased Sinkhorn divergence, the Fractions Skill Score,
// the fair CRPS and Brier scores of an ensemble, and the bootstrap interval of a mean.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include "gnn/eval/bootstrap.h"
#include "gnn/eval/ensemble_scores.h"
#include "gnn/eval/fractions_skill.h"
#include "gnn/eval/sinkhorn.h"

namespace {

torch::Tensor random_cloud(int64_t n, int64_t seed) {
  torch::manual_seed(uint64_t(seed));
  return torch::rand({n, 3}, torch::kFloat64);
}

// A translation adds |d|^2 to every transport cost plus terms that depend on one point only,
// which the marginals fix: OT_eps(a, a + d) = OT_eps(a, a) + |d|^2 exactly, so the divergence is
// |d|^2 at any epsilon.
TEST(SinkhornDivergence, AShiftedCloudCostsTheSquaredShiftAtAnyEpsilon) {
  const auto a = random_cloud(60, 1);
  const auto shift = torch::tensor({0.3, -0.2, 0.1}, torch::kFloat64);
  for (double eps : {0.5, 0.05, 0.005}) {
    gnn::SinkhornSettings s;
    s.epsilon = eps;
    s.tolerance = 1e-9;
    s.max_iterations = 2000;
    EXPECT_NEAR(gnn::sinkhorn_divergence(a, a + shift, s), 0.14, 1e-6) << "epsilon " << eps;
  }
}

TEST(SinkhornDivergence, IsZeroOnACloudItselfAndSymmetric) {
  const auto a = random_cloud(50, 2), b = random_cloud(40, 3) * 0.5 + 0.7;
  gnn::SinkhornSettings s;
  s.epsilon = 0.01;
  EXPECT_NEAR(gnn::sinkhorn_divergence(a, a, s), 0.0, 1e-9);
  const double ab = gnn::sinkhorn_divergence(a, b, s), ba = gnn::sinkhorn_divergence(b, a, s);
  EXPECT_GT(ab, 0.1);
  EXPECT_NEAR(ab, ba, 1e-6 * ab);
}

// With epsilon small against the distances, the divergence of two clouds of equal size tends to
// the squared Wasserstein distance: the cheapest one-to-one assignment's mean squared distance,
// found here by trying every permutation.
TEST(SinkhornDivergence, TendsToTheOptimalAssignmentCostAsEpsilonVanishes) {
  const auto a = random_cloud(6, 4), b = random_cloud(6, 5);
  const auto cost = torch::cdist(a, b).pow(2).contiguous();
  auto c = cost.accessor<double, 2>();
  std::vector<int> order(6);
  std::iota(order.begin(), order.end(), 0);
  double best = 1e30;
  do {
    double sum = 0;
    for (int i = 0; i < 6; ++i) sum += c[i][order[size_t(i)]];
    best = std::min(best, sum / 6);
  } while (std::next_permutation(order.begin(), order.end()));
  gnn::SinkhornSettings s;
  s.epsilon = 1e-4;
  s.max_iterations = 5000;
  EXPECT_NEAR(gnn::sinkhorn_divergence(a, b, s), best, 0.02 * best);
}

TEST(SinkhornDivergence, EmptyCloudsAndBadSettings) {
  gnn::SinkhornSettings s;
  s.epsilon = 0.01;
  const auto none = torch::zeros({0, 3}, torch::kFloat64);
  EXPECT_EQ(gnn::sinkhorn_divergence(none, none, s), 0.0);
  EXPECT_TRUE(std::isnan(gnn::sinkhorn_divergence(none, random_cloud(5, 6), s)));
  s.epsilon = 0;
  EXPECT_THROW(gnn::sinkhorn_divergence(random_cloud(5, 6), random_cloud(5, 7), s),
               std::invalid_argument);
}

// Points at cell centres (cells of 1 m).
torch::Tensor cells(const std::vector<std::pair<double, double>>& at) {
  auto xy = torch::empty({int64_t(at.size()), 2}, torch::kFloat64);
  for (size_t k = 0; k < at.size(); ++k) {
    xy[int64_t(k)][0] = at[k].first + 0.5;
    xy[int64_t(k)][1] = at[k].second + 0.5;
  }
  return xy;
}

// One occupied cell moved (sx, sy) cells, windows of n cells: each fraction field is 1/n^2 on an
// n x n block, the blocks overlap on (n - sx)(n - sy) cells, so FSS = (n - sx)(n - sy) / n^2.
TEST(FractionsSkillScore, OneCellDisplacedScoresItsWindowOverlap) {
  for (int n : {1, 2, 4, 8})
    for (int sx : {0, 1, 3})
      for (int sy : {0, 2}) {
        const double expected =
            sx < n && sy < n ? double((n - sx) * (n - sy)) / double(n * n) : 0.0;
        EXPECT_NEAR(
            gnn::fractions_skill_score(cells({{3 + sx, -2 + sy}}), cells({{3, -2}}), 1.0, n),
            expected, 1e-12)
            << "window " << n << ", shift " << sx << ", " << sy;
      }
}

// Two footprints of two cells each, one cell apart, window 1: the fields are the binary masks,
// one cell shared, so sum (F - O)^2 = 2 and sum F^2 + O^2 = 4: FSS = 0.5.
TEST(FractionsSkillScore, BinaryMasksAtOneCellAndTheEmptyCases) {
  EXPECT_NEAR(gnn::fractions_skill_score(cells({{0, 0}, {1, 0}}), cells({{1, 0}, {2, 0}}), 1.0, 1),
              0.5, 1e-12);
  // Several points in one cell count once.
  EXPECT_NEAR(gnn::fractions_skill_score(cells({{0, 0}, {0, 0}, {0, 0}}), cells({{0, 0}}), 1.0, 3),
              1.0, 1e-12);
  const auto none = torch::zeros({0, 2}, torch::kFloat64);
  EXPECT_EQ(gnn::fractions_skill_score(none, cells({{0, 0}}), 1.0, 2), 0.0);
  EXPECT_TRUE(std::isnan(gnn::fractions_skill_score(none, none, 1.0, 2)));
  EXPECT_THROW(gnn::fractions_skill_score(none, none, 0.0, 2), std::invalid_argument);
}

// For y = 0 and X ~ N(0, 1), CRPS = 2 phi(0) - 1/sqrt(pi) = 0.23369 (Gneiting & Raftery 2007).
// The fair score's mean over many 2-member ensembles drawn from N(0, 1) is that value (the plain
// score's mean would be higher by E|X - X'| / (2K) = 0.28 for K = 2).
TEST(FairEnsembleScores, FairCrpsIsUnbiasedForTheDistributionsScore) {
  std::mt19937_64 random(3);
  std::normal_distribution<double> normal(0, 1);
  const double exact = 2 / std::sqrt(2 * M_PI) - 1 / std::sqrt(M_PI);
  double sum = 0;
  const int draws = 40000;
  for (int k = 0; k < draws; ++k) sum += gnn::fair_crps({normal(random), normal(random)}, 0.0);
  EXPECT_NEAR(sum / draws, exact, 0.01);
  // One member: the absolute error. Two members either side of y: (|a| + |b|) / 2 - |a - b| / 2.
  EXPECT_DOUBLE_EQ(gnn::fair_crps({2.5}, 1.0), 1.5);
  EXPECT_DOUBLE_EQ(gnn::fair_crps({-1.0, 3.0}, 0.0), 2.0 - 2.0);
  EXPECT_DOUBLE_EQ(gnn::fair_crps({1.0, 2.0, 4.0}, 0.0), 7.0 / 3 - 12.0 / 12);
  EXPECT_THROW(gnn::fair_crps({}, 0.0), std::invalid_argument);
}

// Members that each see the event with probability q, the event certain: the fair Brier score's
// expectation is (q - 1)^2, whatever the number of members.
TEST(FairEnsembleScores, FairBrierIsUnbiasedForTheProbabilitysScore) {
  std::mt19937_64 random(4);
  std::bernoulli_distribution member(0.3);
  for (int members : {2, 5}) {
    double sum = 0;
    const int draws = 40000;
    for (int k = 0; k < draws; ++k) {
      int with = 0;
      for (int j = 0; j < members; ++j) with += member(random) ? 1 : 0;
      sum += gnn::fair_brier(with, members, true);
    }
    EXPECT_NEAR(sum / draws, 0.49, 0.01) << members << " members";
  }
  EXPECT_DOUBLE_EQ(gnn::fair_brier(1, 1, false), 1.0);
  EXPECT_DOUBLE_EQ(gnn::fair_brier(4, 4, true), 0.0);
  EXPECT_THROW(gnn::fair_brier(3, 2, true), std::invalid_argument);
}

// The 90 % interval of a mean of n values of spread sigma is about mean +- 1.645 sigma / sqrt(n).
TEST(BootstrapInterval, MatchesTheNormalIntervalOfAMeanAndIsDeterministic) {
  std::mt19937_64 random(5);
  std::normal_distribution<double> normal(2, 1);
  std::vector<double> values(400);
  for (double& v : values) v = normal(random);
  const double m = std::accumulate(values.begin(), values.end(), 0.0) / 400;
  double var = 0;
  for (double v : values) var += (v - m) * (v - m);
  const double half = 1.645 * std::sqrt(var / 399) / std::sqrt(400.0);
  const gnn::Interval i = gnn::bootstrap_mean_interval(values, 0.9, 4000, 7);
  EXPECT_NEAR(i.low, m - half, 0.15 * half);
  EXPECT_NEAR(i.high, m + half, 0.15 * half);
  const gnn::Interval again = gnn::bootstrap_mean_interval(values, 0.9, 4000, 7);
  EXPECT_EQ(i.low, again.low);
  EXPECT_EQ(i.high, again.high);
  const gnn::Interval one = gnn::bootstrap_mean_interval({3.0});
  EXPECT_EQ(one.low, 3.0);
  EXPECT_EQ(one.high, 3.0);
  const gnn::Interval same = gnn::bootstrap_mean_interval({2.0, 2.0, 2.0});
  EXPECT_EQ(same.low, 2.0);
  EXPECT_EQ(same.high, 2.0);
  EXPECT_THROW(gnn::bootstrap_mean_interval({}), std::invalid_argument);
}

}  // namespace
