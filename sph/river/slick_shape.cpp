#include "sph/river/slick_shape.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <utility>
#include <vector>

namespace sph {

namespace {

constexpr double kPi = 3.14159265358979323846;

}  // namespace

SlickShape measure_slick(const FluidParticles& f, Real cell) {
  SlickShape s;
  std::map<std::pair<long, long>, double> oil_in_cell;  // oil volume of the oil particles
  double oil_in_oil_particles = 0;
  for (Index i = 0; i < f.active_count(); ++i) {
    const double oil = double(f.oil_fraction[i]) * double(f.rest_volume[i]);
    s.oil_volume_m3 += oil;
    if (!is_oil(f.oil_fraction[i])) continue;
    const Vec3& p = f.position[i];
    oil_in_cell[{long(std::floor(p.x() / cell)), long(std::floor(p.y() / cell))}] += oil;
    oil_in_oil_particles += oil;
  }
  s.area_m2 = double(oil_in_cell.size()) * double(cell) * double(cell);
  s.equivalent_radius_m = std::sqrt(s.area_m2 / kPi);
  s.mean_thickness_m = s.area_m2 > 0 ? s.oil_volume_m3 / s.area_m2 : 0;
  // Patches: flood fill over the eight neighbours of each cell.
  std::set<std::pair<long, long>> unseen;
  for (const auto& [c, oil] : oil_in_cell) unseen.insert(unseen.end(), c);
  while (!unseen.empty()) {
    ++s.patches;
    double patch_oil = 0;
    std::vector<std::pair<long, long>> stack = {*unseen.begin()};
    unseen.erase(unseen.begin());
    while (!stack.empty()) {
      const auto [x, y] = stack.back();
      stack.pop_back();
      patch_oil += oil_in_cell.at({x, y});
      for (long dx = -1; dx <= 1; ++dx)
        for (long dy = -1; dy <= 1; ++dy) {
          const auto it = unseen.find({x + dx, y + dy});
          if (it == unseen.end()) continue;
          stack.push_back(*it);
          unseen.erase(it);
        }
    }
    if (oil_in_oil_particles > 0)
      s.largest_patch_share = std::max(s.largest_patch_share, patch_oil / oil_in_oil_particles);
  }
  return s;
}

}  // namespace sph
