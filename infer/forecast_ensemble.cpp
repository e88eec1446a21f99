#include "infer/forecast_ensemble.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace infer {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// A figure for JSON: null where not finite (no member defines it, or after the forecast's end).
nlohmann::json figure(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nullptr;
}

nlohmann::json spread_json(const Spread& s) {
  return {{"mean", figure(s.mean)},
          {"q10", figure(s.q10)},
          {"q50", figure(s.q50)},
          {"q90", figure(s.q90)},
          {"members", s.members}};
}

// Per frame, the spread of one figure over the members.
nlohmann::json spreads_over_frames(const std::vector<MemberTrack>& members, size_t frames,
                                   std::vector<double> MemberTrack::*field) {
  nlohmann::json out = nlohmann::json::array();
  for (size_t f = 0; f < frames; ++f) {
    std::vector<double> values;
    for (const auto& m : members) values.push_back((m.*field)[f]);
    out.push_back(spread_json(spread_of(values)));
  }
  return out;
}

}  // namespace

std::pair<double, double> oil_centroid(const sph::FluidParticles& fluid) {
  double x = 0, y = 0;
  long n = 0;
  for (sph::Index i = 0; i < fluid.active_count(); ++i)
    if (sph::is_oil(fluid.oil_fraction[i])) {
      x += double(fluid.position[i].x());
      y += double(fluid.position[i].y());
      ++n;
    }
  if (n == 0) return {kNaN, kNaN};
  return {x / double(n), y / double(n)};
}

MemberTrack member_track(const sph::SpillMetrics& spill,
                         const std::vector<std::pair<double, double>>& centroids) {
  if (spill.frames().size() != centroids.size())
    throw std::invalid_argument("member_track: a centroid per measured frame");
  MemberTrack t;
  for (size_t f = 0; f < centroids.size(); ++f) {
    t.front.push_back(spill.frames()[f].front_distance_m);
    t.slick_area.push_back(spill.frames()[f].slick_area_m2);
    t.centroid_x.push_back(centroids[f].first);
    t.centroid_y.push_back(centroids[f].second);
  }
  for (const auto& w : spill.watch_points()) t.arrival[w.name] = spill.arrival(w.name);
  return t;
}

double quantile_of_sorted(const std::vector<double>& sorted, double q) {
  if (sorted.empty() || !(q >= 0 && q <= 1))
    throw std::invalid_argument("quantile_of_sorted: values and 0 <= q <= 1");
  const double at = q * double(sorted.size() - 1);
  const size_t below = size_t(std::floor(at));
  const size_t above = std::min(below + 1, sorted.size() - 1);
  const double w = at - double(below);
  // An infinite neighbour with no weight does not turn the quantile into NaN (0 x inf).
  if (w == 0 || sorted[below] == sorted[above]) return sorted[below];
  return sorted[below] + w * (sorted[above] - sorted[below]);
}

Spread spread_of(std::vector<double> values) {
  values.erase(
      std::remove_if(values.begin(), values.end(), [](double v) { return !std::isfinite(v); }),
      values.end());
  Spread s;
  s.members = int(values.size());
  if (values.empty()) return {kNaN, kNaN, kNaN, kNaN, 0};
  std::sort(values.begin(), values.end());
  double sum = 0;
  for (double v : values) sum += v;
  s.mean = sum / double(values.size());
  s.q10 = quantile_of_sorted(values, 0.1);
  s.q50 = quantile_of_sorted(values, 0.5);
  s.q90 = quantile_of_sorted(values, 0.9);
  return s;
}

nlohmann::json ensemble_summary(const std::vector<MemberTrack>& members,
                                const std::vector<double>& times) {
  if (members.empty()) throw std::invalid_argument("ensemble_summary: no members");
  const size_t frames = times.size();
  for (const auto& m : members)
    if (m.front.size() != frames || m.slick_area.size() != frames ||
        m.centroid_x.size() != frames || m.centroid_y.size() != frames)
      throw std::invalid_argument("ensemble_summary: every member measures every frame");
  nlohmann::json arrivals = nlohmann::json::object();
  for (const auto& [name, ignored] : members.front().arrival) {
    std::vector<double> at;  // +inf: not within the forecast
    for (const auto& m : members) {
      const auto a = m.arrival.find(name);
      at.push_back(a != m.arrival.end() && a->second ? *a->second : kInf);
    }
    std::sort(at.begin(), at.end());
    nlohmann::json reached = nlohmann::json::array();
    for (double t : times) {
      const auto by_then = std::upper_bound(at.begin(), at.end(), t) - at.begin();
      reached.push_back(double(by_then) / double(members.size()));
    }
    const long arrived = std::count_if(at.begin(), at.end(), [](double t) { return t < kInf; });
    arrivals[name] = {{"share_reached", double(arrived) / double(members.size())},
                      {"q10", figure(quantile_of_sorted(at, 0.1))},
                      {"q50", figure(quantile_of_sorted(at, 0.5))},
                      {"q90", figure(quantile_of_sorted(at, 0.9))},
                      {"share_reached_by_frame", reached}};
  }
  nlohmann::json per_member = nlohmann::json::array();
  for (const auto& m : members) {
    nlohmann::json arrival = nlohmann::json::object();
    for (const auto& [name, t] : m.arrival) arrival[name] = t ? nlohmann::json(*t) : nullptr;
    per_member.push_back({{"front_m", figure(m.front.back())},
                          {"slick_area_m2", figure(m.slick_area.back())},
                          {"centroid_x_m", figure(m.centroid_x.back())},
                          {"centroid_y_m", figure(m.centroid_y.back())},
                          {"arrival_s", arrival}});
  }
  return {{"members", members.size()},
          {"t", times},
          {"front_m", spreads_over_frames(members, frames, &MemberTrack::front)},
          {"slick_area_m2", spreads_over_frames(members, frames, &MemberTrack::slick_area)},
          {"centroid_x_m", spreads_over_frames(members, frames, &MemberTrack::centroid_x)},
          {"centroid_y_m", spreads_over_frames(members, frames, &MemberTrack::centroid_y)},
          {"watch_point_arrival_s", arrivals},
          {"last_frame_by_member", per_member},
          {"note",
           "per frame over the members that define a figure (a member without oil has no "
           "centroid): mean and 10/50/90 % quantiles (linear between order statistics); "
           "arrival: first time (s) oil came within the watch point, a member that never did "
           "counting as after the forecast's end (a quantile there is null); "
           "share_reached_by_frame: the share of members whose oil had reached it by each t"}};
}

void OilingMap::measure(int frame, const sph::FluidParticles& fluid) {
  std::set<std::pair<long, long>> now;
  for (sph::Index i = 0; i < fluid.active_count(); ++i)
    if (sph::is_oil(fluid.oil_fraction[i]))
      now.insert({long(std::floor(double(fluid.position[i].x()) / cell_)),
                  long(std::floor(double(fluid.position[i].y()) / cell_))});
  for (size_t m = 0; m < frames_.size(); ++m)
    if (frames_[m] == frame) member_cells_[m] = now;
  member_cells_.back().insert(now.begin(), now.end());
}

void OilingMap::end_member() {
  for (size_t m = 0; m < member_cells_.size(); ++m) {
    for (const auto& key : member_cells_[m]) ++cells_[m][key];
    member_cells_[m].clear();
  }
}

std::map<std::pair<long, long>, double> OilingMap::shares(size_t moment, int members) const {
  std::map<std::pair<long, long>, double> out;
  for (const auto& [key, count] : cells_.at(moment)) out[key] = double(count) / double(members);
  return out;
}

std::vector<common::RgbImage> OilingMap::render(
    const common::FrameRenderer& renderer, const std::vector<std::vector<common::Point>>& water,
    float top, int members) const {
  std::vector<common::RgbImage> pictures;
  for (size_t m = 0; m < cells_.size(); ++m) {
    std::vector<common::Point> at = water.at(std::min(m, water.size() - 1));
    std::vector<float> shade(at.size(), 0.0f);
    for (const auto& [key, share] : shares(m, members)) {
      at.emplace_back(float((double(key.first) + 0.5) * cell_),
                      float((double(key.second) + 0.5) * cell_), top);
      shade.push_back(float(share));
    }
    pictures.push_back(renderer.render(at, shade, common::ViewAxis::kRiver));
  }
  return pictures;
}

}  // namespace infer
