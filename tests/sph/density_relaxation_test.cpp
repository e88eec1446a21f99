// The constant-density correction that relaxes learned frames
// (sph/simulation/density_relaxation.h): it removes compression, and leaves a frame already at rest
// density where it is.
#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>

#include <nlohmann/json.hpp>

#include "sph/scene/scene_loader.h"
#include "sph/simulation/density_relaxation.h"
#include "sph/simulation/simulation.h"

namespace {

const char* kTank = R"({
  "name": "tank", "particle_radius": 0.02, "end_time": 0.1,
  "boxes": [{"min": [0, 0, 0], "max": [0.4, 0.4, 0.4]}],
  "fluid_blocks": [{"min": [0, 0, 0], "max": [0.4, 0.4, 0.2]}]})";

TEST(DensityRelaxation, RemovesCompressionAndLeavesARestingFrameAlone) {
  const sph::LoadedScene s = sph::parse_scene(nlohmann::json::parse(kTank), "tank.json");
  const sph::Simulation sim(s.config);
  std::vector<sph::Vec3> rest(sim.fluid().position.begin(),
                              sim.fluid().position.begin() + sim.fluid().active_count());
  const std::vector<sph::Real> water(rest.size(), 0);
  ASSERT_EQ(rest.size(), 500u);
  sph::DensityRelaxation relaxation(s.config);

  // The lattice at rest: almost no compression, and the correction barely moves it (< 1 % of a
  // particle diameter).
  auto still = rest;
  const auto [rest_before, rest_after] = relaxation.relax(still, water, 3);
  EXPECT_LT(rest_before.mean, 0.01);
  double largest_move = 0;
  for (size_t i = 0; i < rest.size(); ++i)
    largest_move = std::max(largest_move, double((still[i] - rest[i]).norm()));
  EXPECT_LT(largest_move, 0.01 * 0.04);

  // Squeezed to 85 % of its height (13 % mean compression, far more than a learned frame has):
  // each iteration removes part of it, as the solver's own iterations do; measured 0.126 ->
  // 0.067 (1 iteration), 0.039 (5), 0.0021 (20). Bound: 20 iterations cut it at least tenfold.
  auto squeezed = rest;
  for (auto& x : squeezed) x.z() *= sph::Real(0.85);
  const auto [before, after] = relaxation.relax(squeezed, water, 20);
  std::cout << "compression mean " << before.mean << " -> " << after.mean << ", p95 " << before.p95
            << " -> " << after.p95 << "\n";
  EXPECT_GT(before.mean, 0.05);
  EXPECT_LT(after.mean, before.mean / 10);
  EXPECT_EQ(after.particles, 500);
  // measure() agrees with what relax() reported, without moving anything.
  const auto measured = relaxation.measure(squeezed, water);
  EXPECT_NEAR(measured.mean, after.mean, 1e-9);
  // A frame compressed against the top of the box: the correction keeps every particle inside
  // the domain (a learned frame once pushed one out and stopped the rollout).
  auto against_lid = rest;
  for (auto& x : against_lid) x.z() = sph::Real(0.4) - (sph::Real(0.2) - x.z()) * sph::Real(0.3);
  relaxation.relax(against_lid, water, 5);
  for (const auto& x : against_lid) {
    EXPECT_TRUE(x.allFinite());
    EXPECT_LE(x.z(), sim.domain().max.z());
  }
  // A particle outside the domain is left where it is.
  auto with_stray = rest;
  with_stray[0] = sph::Vec3(5, 5, 5);
  relaxation.relax(with_stray, water, 2);
  EXPECT_EQ(with_stray[0], sph::Vec3(5, 5, 5));
}

}  // namespace
