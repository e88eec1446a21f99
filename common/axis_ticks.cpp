#include "common/axis_ticks.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace common {

double round_up_to_125(double x) {
  const double decade = std::pow(10.0, std::floor(std::log10(x)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    // A relative slack so that 0.2 (stored a hair above) stays 0.2 rather than becoming 0.5.
    if (m * decade >= x * (1 - 1e-9)) return m * decade;
  return 10 * decade;
}

std::string tick_label(double value, double step) {
  // Decimals of the step itself (0.25 needs 2, 0.2 needs 1, 5 needs 0).
  int decimals = 0;
  for (double s = step; decimals < 12 && std::abs(s - std::round(s)) > 1e-6 * std::abs(s); s *= 10)
    ++decimals;
  if (std::abs(value) < 1e-9 * step) value = 0;  // never "-0"
  char text[64];
  const double magnitude = std::max(std::abs(value), step);
  if (magnitude >= 1e6 || magnitude < 1e-4)
    std::snprintf(text, sizeof text, "%.3g", value);  // very large or small: exponent form
  else
    std::snprintf(text, sizeof text, "%.*f", decimals, value);
  return text;
}

AxisTicks linear_ticks(double lo, double hi, int target) {
  if (!(hi > lo)) {
    const double half = lo == 0 ? 0.5 : std::abs(lo) * 0.5;
    lo -= half;
    hi += half;
  }
  AxisTicks t;
  t.step = round_up_to_125((hi - lo) / double(std::max(1, target)));
  t.lo = std::floor(lo / t.step + 1e-9) * t.step;
  t.hi = std::ceil(hi / t.step - 1e-9) * t.step;
  const long count = std::lround((t.hi - t.lo) / t.step);
  for (long k = 0; k <= count; ++k) {
    const double v = t.lo + double(k) * t.step;
    t.values.push_back(v);
    t.labels.push_back(tick_label(v, t.step));
  }
  return t;
}

AxisTicks log_ticks(double log_lo, double log_hi) {
  AxisTicks t;
  const double first = std::floor(log_lo + 1e-9), last = std::ceil(log_hi - 1e-9);
  t.lo = first;
  t.hi = std::max(last, first + 1);
  // One tick per decade up to six decades, then every second or fifth.
  t.step = round_up_to_125(std::max(1.0, (t.hi - t.lo) / 6));
  for (double e = t.lo; e <= t.hi + 1e-9; e += t.step) {
    t.values.push_back(e);
    char text[32];
    std::snprintf(text, sizeof text, "1e%d", int(std::lround(e)));
    const double v = std::pow(10.0, e);
    // Plain numbers between 0.001 and 10000, exponents beyond.
    t.labels.push_back(e >= -3 && e <= 4 ? tick_label(v, v) : std::string(text));
  }
  return t;
}

}  // namespace common
