#include "sph/river/spill_metrics.h"

#include "common/svg_plot.h"
#include "sph/core/simulation_error.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

#include "sph/core/config.h"

namespace sph {

namespace {

// The definitions of the slick's shape, the same in river and still-water spill.json.
nlohmann::json slick_shape_definitions() {
  return {{"oil", "a particle with oil volume fraction >= 0.5"},
          {"slick_area_m2", "top-view cells one particle diameter wide that hold oil"},
          {"equivalent_radius_m", "radius of a disc of the slick's area"},
          {"patches", "separate pieces of the slick (cells joined by an edge or a corner)"},
          {"largest_patch_share",
           "share of the oil in oil particles that lies in the largest patch (0 without oil)"}};
}

}  // namespace

SpillMetrics::SpillMetrics(const Terrain& terrain, Real water_level, Real leak_x, Real cell,
                           std::vector<WatchPointConfig> watch_points)
    : leak_x_(leak_x), cell_(cell), x0_(terrain.origin_x), watch_points_(std::move(watch_points)) {
  // The water's edges along the river, one bin a particle diameter long: where the wet cells
  // of the terrain (in the mask, ground below the surface) end on either side.
  const int bins = int(std::ceil((terrain.max_x() - x0_) / cell)) + 1;
  const Real nan = std::numeric_limits<Real>::quiet_NaN();
  left_edge_.assign(size_t(bins), nan);
  right_edge_.assign(size_t(bins), nan);
  for (int b = 0; b < bins; ++b) {
    const Real x = x0_ + (Real(b) + Real(0.5)) * cell;
    for (int iy = 0; iy < terrain.ny; ++iy) {
      const Real y = terrain.origin_y + terrain.cell_size * Real(iy);
      if (!terrain.is_water(x, y) || terrain.height_at(x, y) >= water_level) continue;
      Real& left = left_edge_[size_t(b)];
      Real& right = right_edge_[size_t(b)];
      left = std::isnan(left) ? y : std::max(left, y);
      right = std::isnan(right) ? y : std::min(right, y);
    }
  }
}

const SpillFrame& SpillMetrics::measure(const FluidParticles& f, double t, double oil_released) {
  SpillFrame frame;
  frame.t = t;
  frame.oil_released_m3 = oil_released;
  frame.slick = measure_slick(f, cell_);
  frame.oil_in_reach_m3 = frame.slick.oil_volume_m3;
  frame.slick_area_m2 = frame.slick.area_m2;
  bool any_oil = false;
  for (Index i = 0; i < f.active_count(); ++i) {
    if (!is_oil(f.oil_fraction[i])) continue;
    const Vec3& p = f.position[i];
    const double ahead = double(p.x() - leak_x_);
    frame.front_distance_m = any_oil ? std::max(frame.front_distance_m, ahead) : ahead;
    any_oil = true;
    const long b = long(std::floor((p.x() - x0_) / cell_));
    if (b >= 0 && size_t(b) < left_edge_.size() && !std::isnan(left_edge_[size_t(b)])) {
      if (p.y() >= left_edge_[size_t(b)] - cell_) left_bins_.insert(b);
      if (p.y() <= right_edge_[size_t(b)] + cell_) right_bins_.insert(b);
    }
    for (const auto& w : watch_points_) {
      const Real dx = p.x() - w.x, dy = p.y() - w.y;
      if (dx * dx + dy * dy <= w.radius * w.radius && !arrival_.count(w.name)) arrival_[w.name] = t;
    }
  }
  frame.front_distance_m = std::max(0.0, frame.front_distance_m);
  frame.left_bank_m = double(left_bins_.size()) * double(cell_);
  frame.right_bank_m = double(right_bins_.size()) * double(cell_);
  frames_.push_back(frame);
  return frames_.back();
}

std::optional<double> SpillMetrics::arrival(const std::string& name) const {
  const auto it = arrival_.find(name);
  if (it == arrival_.end()) return std::nullopt;
  return it->second;
}

nlohmann::json SpillMetrics::to_json() const {
  nlohmann::json frames = nlohmann::json::array();
  for (const auto& f : frames_)
    frames.push_back({{"t", f.t},
                      {"slick_area_m2", f.slick_area_m2},
                      {"front_distance_m", f.front_distance_m},
                      {"left_bank_oiled_m", f.left_bank_m},
                      {"right_bank_oiled_m", f.right_bank_m},
                      {"oil_released_m3", f.oil_released_m3},
                      {"oil_in_reach_m3", f.oil_in_reach_m3},
                      {"equivalent_radius_m", f.slick.equivalent_radius_m},
                      {"mean_thickness_m", f.slick.mean_thickness_m},
                      {"patches", f.slick.patches},
                      {"largest_patch_share", f.slick.largest_patch_share}});
  nlohmann::json arrivals = nlohmann::json::object();
  for (const auto& w : watch_points_) {
    const auto a = arrival(w.name);
    arrivals[w.name] = a ? nlohmann::json(*a) : nlohmann::json(nullptr);
  }
  auto first_contact = [&](double SpillFrame::*side) {
    for (const auto& f : frames_)
      if (f.*side > 0) return nlohmann::json(f.t);
    return nlohmann::json(nullptr);
  };
  nlohmann::json definitions = slick_shape_definitions();
  definitions.update(nlohmann::json{
      {"front_distance_m", "furthest oil downstream (+x) of the leak"},
      {"left_bank_oiled_m",
       "length along the river of the left (+y) bank that oil has come within a particle "
       "diameter of, so far"},
      {"right_bank_oiled_m", "the same for the right bank"},
      {"oil_released_m3", "oil released by the leaks so far"},
      {"oil_in_reach_m3", "oil volume in the active particles"},
      {"mean_thickness_m", "oil volume in the active particles over the slick's area"},
      {"arrival_s", "first frame with oil within the watch point's radius (null: never)"}});
  return {{"definitions", definitions},
          {"leak_x_m", leak_x_},
          {"cell_m", cell_},
          {"first_left_bank_contact_s", first_contact(&SpillFrame::left_bank_m)},
          {"first_right_bank_contact_s", first_contact(&SpillFrame::right_bank_m)},
          {"arrival_s", arrivals},
          {"frames", frames}};
}

void write_spill_plot(const std::string& path, const std::vector<SpillFrame>& frames,
                      const std::string& title) {
  // Three panels over a shared time axis.
  auto series = [&](const char* name, double SpillFrame::*value) {
    common::PlotSeries s{name, {}, {}};
    for (const auto& f : frames) {
      s.x.push_back(f.t);
      s.y.push_back(f.*value);
    }
    return s;
  };
  common::write_panels(
      path, title,
      {{"t (s)", "slick area (m^2)", {series("area", &SpillFrame::slick_area_m2)}, false},
       {"t (s)",
        "leading edge downstream of the leak (m)",
        {series("front", &SpillFrame::front_distance_m)},
        false},
       {"t (s)",
        "bank oiled (m)",
        {series("left bank", &SpillFrame::left_bank_m),
         series("right bank", &SpillFrame::right_bank_m)},
        false}});
}

void StillWaterSlickMetrics::measure(const FluidParticles& fluid, double t) {
  frames_.emplace_back(t, measure_slick(fluid, cell_));
}

nlohmann::json StillWaterSlickMetrics::to_json() const {
  nlohmann::json frames = nlohmann::json::array();
  for (const auto& [t, s] : frames_)
    frames.push_back({{"t", t},
                      {"slick_area_m2", s.area_m2},
                      {"equivalent_radius_m", s.equivalent_radius_m},
                      {"mean_thickness_m", s.mean_thickness_m},
                      {"patches", s.patches},
                      {"largest_patch_share", s.largest_patch_share},
                      {"oil_volume_m3", s.oil_volume_m3}});
  nlohmann::json definitions = slick_shape_definitions();
  definitions.update(nlohmann::json{
      {"mean_thickness_m", "oil volume over the slick's area"},
      {"oil_volume_m3", "oil volume in the active particles"},
      {"fay_gravity_inertia",
       "fit of A - A0 = c t^slope to the area, from the frame where the slick has grown by a "
       "fifth of its released area to the last before its mean thickness falls below two "
       "particle diameters; k1 = sqrt(c / (pi (Delta g V)^(1/2))) from the rate of a fit at "
       "slope 1 (Fay: slope 1, k1 1.14); null for a run that starts without oil (a pour) or "
       "with fewer than three frames in the window"}});
  const FayFit fay = fit_fay_gravity_inertia(frames_, delta_, gravity_, cell_);
  nlohmann::json fit = nullptr;
  if (fay.valid)
    fit = {{"window_s", {fay.window_start_s, fay.window_end_s}},
           {"frames", fay.frames},
           {"slope", fay.slope},
           {"k1", fay.k1},
           {"fay_k1", kFayK1}};
  return {{"definitions", definitions},
          {"cell_m", cell_},
          {"fay_gravity_inertia", fit},
          {"frames", frames}};
}

void write_slick_plot(const std::string& path,
                      const std::vector<std::pair<double, SlickShape>>& frames,
                      const std::string& title) {
  auto series = [&](const char* name, double (*value)(const SlickShape&)) {
    common::PlotSeries s{name, {}, {}};
    for (const auto& [t, shape] : frames) {
      s.x.push_back(t);
      s.y.push_back(value(shape));
    }
    return s;
  };
  common::write_panels(
      path, title,
      {{"t (s)",
        "slick area (m^2)",
        {series("area", [](const SlickShape& s) { return s.area_m2; })},
        false},
       {"t (s)",
        "mean thickness (m)",
        {series("thickness", [](const SlickShape& s) { return s.mean_thickness_m; })},
        false},
       {"t (s)",
        "patches",
        {series("patches", [](const SlickShape& s) { return double(s.patches); })},
        false}});
}

}  // namespace sph
