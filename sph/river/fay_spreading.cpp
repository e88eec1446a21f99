#include "sph/river/fay_spreading.h"

#include <cmath>

namespace sph {

FayFit fit_fay_gravity_inertia(const std::vector<std::pair<double, SlickShape>>& frames,
                               double relative_density_difference, double gravity, double diameter,
                               const FayWindow& window) {
  FayFit fit;
  if (frames.empty() || relative_density_difference <= 0 || gravity <= 0) return fit;
  const double t0 = frames.front().first, a0 = frames.front().second.area_m2;
  const double volume = frames.front().second.oil_volume_m3;
  if (a0 <= 0 || volume <= 0) return fit;
  // Sums for the log-log slope and for the rate through the origin (A - A0 = c t).
  double sx = 0, sy = 0, sxx = 0, sxy = 0, st2 = 0, sta = 0;
  bool open = false;
  for (const auto& [t_abs, shape] : frames) {
    const double t = t_abs - t0, growth = shape.area_m2 - a0;
    if (t <= 0 || (!open && growth < window.start_growth * a0)) continue;
    // The window closes where the slick thins to the resolution, or if it shrinks back.
    if (shape.mean_thickness_m < window.end_thickness_diameters * diameter || growth <= 0) break;
    if (!open) open = true, fit.window_start_s = t_abs;
    fit.window_end_s = t_abs;
    ++fit.frames;
    const double x = std::log(t), y = std::log(growth);
    sx += x, sy += y, sxx += x * x, sxy += x * y;
    st2 += t * t, sta += t * growth;
  }
  const double n = fit.frames, spread = n * sxx - sx * sx;
  if (fit.frames < 3 || spread <= 0) return fit;
  fit.valid = true;
  fit.slope = (n * sxy - sx * sy) / spread;
  const double rate = sta / st2;
  fit.k1 = std::sqrt(rate / (M_PI * std::sqrt(relative_density_difference * gravity * volume)));
  return fit;
}

}  // namespace sph
