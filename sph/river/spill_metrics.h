#pragma once
// What a responder reads off a river spill, frame by frame (spill.json of a run): the slick's
// area seen from above, how far downstream of the leak its leading edge is, how much of each bank
// it has touched, the oil released and the oil still in the reach, and when it reached each
// watch point. A particle counts as oil when its oil fraction is at least 1/2.

#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "sph/core/particle_set.h"
#include "sph/river/fay_spreading.h"
#include "sph/river/river_configs.h"
#include "sph/river/slick_shape.h"
#include "sph/river/terrain.h"

namespace sph {

struct SpillFrame {
  double t = 0;
  double slick_area_m2 = 0;     // top-view cells a particle diameter wide holding oil
  double front_distance_m = 0;  // furthest oil downstream of the leak (0 before any)
  double left_bank_m = 0;       // length along the river of the left (+y) bank touched by oil
  double right_bank_m = 0;      // same for the right bank
  double oil_released_m3 = 0;   // by the leaks so far
  double oil_in_reach_m3 = 0;   // oil volume of the active particles
  SlickShape slick;             // area, equivalent radius, mean thickness, patches
};

class SpillMetrics {
 public:
  // `leak_x`: where the leak is, for the front distance; `cell` the particle diameter.
  SpillMetrics(const Terrain& terrain, Real water_level, Real leak_x, Real cell,
               std::vector<WatchPointConfig> watch_points);

  // Measures the active particles at time t; `oil_released` is the leaks' output so far.
  const SpillFrame& measure(const FluidParticles& fluid, double t, double oil_released);

  const std::vector<SpillFrame>& frames() const { return frames_; }
  // First time oil came within a watch point's radius; absent if it never did.
  std::optional<double> arrival(const std::string& name) const;
  const std::vector<WatchPointConfig>& watch_points() const { return watch_points_; }
  nlohmann::json to_json() const;

 private:
  Real leak_x_, cell_;
  Real x0_;                                   // start of the first bank bin
  std::vector<Real> left_edge_, right_edge_;  // wet extent of each bin along x (y max, y min)
  std::vector<WatchPointConfig> watch_points_;
  std::map<std::string, double> arrival_;
  std::set<long> left_bins_, right_bins_;  // bank bins oil has touched so far
  std::vector<SpillFrame> frames_;
};

// The slick of oil released on still water (a tank, no river): its shape frame by frame, for
// spill.json and its plot, and the fit of Fay's gravity-inertia law to its growth.
class StillWaterSlickMetrics {
 public:
  // `relative_density_difference`: (rho_water - rho_oil) / rho_water; `gravity` in m/s^2.
  StillWaterSlickMetrics(Real cell, double relative_density_difference, double gravity)
      : cell_(cell), delta_(relative_density_difference), gravity_(gravity) {}
  void measure(const FluidParticles& fluid, double t);
  const std::vector<std::pair<double, SlickShape>>& frames() const { return frames_; }
  nlohmann::json to_json() const;

 private:
  Real cell_;
  double delta_, gravity_;
  std::vector<std::pair<double, SlickShape>> frames_;
};

// Draws the still-water slick's area, radius, thickness and patches against time.
void write_slick_plot(const std::string& path,
                      const std::vector<std::pair<double, SlickShape>>& frames,
                      const std::string& title);

// Draws slick area, front distance and bank contact against time as an SVG picture.
void write_spill_plot(const std::string& path, const std::vector<SpillFrame>& frames,
                      const std::string& title);

}  // namespace sph
